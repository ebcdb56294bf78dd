#include "fieldlidar/io/file_util.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <system_error>

#include "fieldlidar/core/error.hpp"

namespace fieldlidar::io {

namespace fs = std::filesystem;

std::vector<std::byte> read_file_bytes(const fs::path& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw Error(path.string() + ": no such file");
  if (fs::is_directory(path, ec)) throw Error(path.string() + ": is a folder, expected a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path.string() + ": cannot open for reading");
  in.seekg(0, std::ios::end);
  const auto size = in.tellg();
  if (size < 0) throw Error(path.string() + ": cannot determine its size");
  in.seekg(0);
  std::vector<std::byte> bytes(static_cast<std::size_t>(size));
  if (size > 0 && !in.read(reinterpret_cast<char*>(bytes.data()), size))
    throw Error(path.string() + ": read failed");
  return bytes;
}

std::string extension_of(const fs::path& path) {
  std::string ext = path.extension().string();
  if (!ext.empty() && ext[0] == '.') ext.erase(0, 1);
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

namespace {

const char* kind_of(const struct stat& st) {
  if (S_ISLNK(st.st_mode)) return "a symbolic link";
  if (S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode)) return "a device";
  if (S_ISFIFO(st.st_mode)) return "a FIFO";
  if (S_ISSOCK(st.st_mode)) return "a socket";
  return "not a regular file";
}

std::string errno_text(int err) {
  return std::strerror(err);
}

}  // namespace

void check_writable(const fs::path& path, bool overwrite, const std::vector<fs::path>& inputs) {
  const std::string name = path.string();
  struct stat st {};
  if (::lstat(path.c_str(), &st) == 0) {
    if (S_ISDIR(st.st_mode)) throw Error(name + ": is a folder, expected a file name");
    if (!S_ISREG(st.st_mode))
      throw Error(name + ": is " + kind_of(st) + "; only a regular file is ever replaced");
    if (!overwrite) throw Error(name + ": already exists (pass --force to replace it)");
    for (const auto& in : inputs) {
      struct stat si {};
      if (::stat(in.c_str(), &si) == 0 && si.st_dev == st.st_dev && si.st_ino == st.st_ino)
        throw Error(name + ": is the input " + in.string() +
                    "; write to another file (it would replace the data being read)");
    }
  }
  const auto parent = path.parent_path();
  std::error_code ec;
  if (!parent.empty() && !fs::is_directory(parent, ec))
    throw Error(name + ": folder " + parent.string() + " does not exist");
}

void write_file_atomic(const fs::path& path, const void* data, std::size_t size, bool overwrite) {
  check_writable(path, overwrite);
  static std::atomic<unsigned> counter{0};
  const std::string name = path.string();
  fs::path tmp;
  int fd = -1;
  for (int attempt = 0; attempt < 100 && fd < 0; ++attempt) {
    tmp = path;
    tmp += ".tmp" + std::to_string(::getpid()) + "." + std::to_string(counter++);
    fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0 && errno != EEXIST)
      throw Error(name + ": cannot create a file in its folder: " + errno_text(errno));
  }
  if (fd < 0) throw Error(name + ": cannot create a temporary file beside it");
  auto fail = [&](const std::string& what, int err) {
    if (fd >= 0) ::close(fd);
    ::unlink(tmp.c_str());
    throw Error(name + ": " + what + ": " + errno_text(err) + "; the file was not written");
  };
  const auto* p = static_cast<const char*>(data);
  std::size_t left = size;
  while (left > 0) {
    const ssize_t n = ::write(fd, p, left);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) fail("write failed", n < 0 ? errno : ENOSPC);
    p += n;
    left -= static_cast<std::size_t>(n);
  }
  // fsync is cheap next to the work that produced the data; EINVAL means the file system does
  // not support it (nothing to flush).
  if (::fsync(fd) != 0 && errno != EINVAL && errno != EROFS) fail("flush to disk failed", errno);
  const int closed = ::close(fd);
  fd = -1;
  if (closed != 0) fail("close failed", errno);
  try {
    check_writable(path, overwrite);  // nothing took its place meanwhile
  } catch (...) {
    ::unlink(tmp.c_str());
    throw;
  }
  if (::rename(tmp.c_str(), path.c_str()) != 0)
    fail("cannot move the written file into place", errno);
}

}  // namespace fieldlidar::io
