#include "fieldlidar/io/pcd.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <sstream>
#include <string_view>
#include <vector>

#include <pcl/io/lzf.h>
#include <pcl/io/pcd_io.h>

#include "fieldlidar/core/error.hpp"
#include "pcd_header.hpp"
#include "pcl_fields.hpp"
#include "text_tokens.hpp"

namespace fieldlidar::io {

namespace {

using Field = pcl::PCLPointField;
using detail::PcdHeader;

std::uint32_t get_u32(std::span<const std::byte> b, std::size_t at) {
  std::uint32_t v;
  std::memcpy(&v, b.data() + at, 4);
  return v;
}

/// ASCII body: whitespace-separated numbers, one point per line, every value parsed strictly.
void parse_ascii_body(std::span<const std::byte> bytes, const PcdHeader& h,
                      pcl::PCLPointCloud2& blob, const std::string& source) {
  std::string_view text(reinterpret_cast<const char*>(bytes.data()) + h.data_offset,
                        bytes.size() - h.data_offset);
  std::size_t elems = 0;
  for (auto c : h.counts) elems += c;
  std::uint64_t idx = 0;
  std::size_t line_no = 0;
  while (!text.empty()) {
    ++line_no;
    const auto eol = text.find('\n');
    const auto line = text.substr(0, eol);
    text = eol == std::string_view::npos ? std::string_view{} : text.substr(eol + 1);
    const auto tok = detail::split_tokens(line);
    if (tok.empty()) continue;
    if (idx >= h.points)
      detail::pcd_fail(source,
                       "has more than the " + std::to_string(h.points) + " points of its header");
    if (tok.size() != elems)
      detail::pcd_fail(source, "data line " + std::to_string(line_no) + " has " +
                                   std::to_string(tok.size()) + " values, expected " +
                                   std::to_string(elems));
    std::uint8_t* out = blob.data.data() + idx * blob.point_step;
    std::size_t t = 0;
    for (std::size_t f = 0; f < h.names.size(); ++f) {
      for (unsigned c = 0; c < h.counts[f]; ++c, ++t) {
        double v = 0.0;
        std::string_view s = tok[t];
        if (!s.empty() && s[0] == '+') s.remove_prefix(1);
        const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
        if (ec != std::errc() || ptr != s.data() + s.size())
          detail::pcd_fail(source, "data line " + std::to_string(line_no) + ": '" +
                                       std::string(tok[t]) + "' is not a number");
        const auto type = detail::pcd_pcl_type(h.types[f], h.sizes[f]);
        auto put = [&](auto typed) {
          using T = decltype(typed);
          if constexpr (std::is_floating_point_v<T>) {
            typed = static_cast<T>(v);
          } else {
            const double lo = static_cast<double>(std::numeric_limits<T>::lowest());
            const double hi = static_cast<double>(std::numeric_limits<T>::max());
            typed = std::isfinite(v) ? static_cast<T>(std::clamp(v, lo, hi)) : T{0};
          }
          std::memcpy(out, &typed, sizeof(T));
          out += sizeof(T);
        };
        switch (type) {
          case Field::FLOAT32:
            put(float{});
            break;
          case Field::FLOAT64:
            put(double{});
            break;
          case Field::INT8:
            put(std::int8_t{});
            break;
          case Field::UINT8:
            put(std::uint8_t{});
            break;
          case Field::INT16:
            put(std::int16_t{});
            break;
          case Field::UINT16:
            put(std::uint16_t{});
            break;
          case Field::INT32:
            put(std::int32_t{});
            break;
          case Field::UINT32:
            put(std::uint32_t{});
            break;
          case Field::INT64:
            put(std::int64_t{});
            break;
          default:
            put(std::uint64_t{});
            break;
        }
      }
    }
    ++idx;
  }
  if (idx != h.points)
    detail::pcd_fail(source, "truncated: " + std::to_string(idx) + " data lines for " +
                                 std::to_string(h.points) + " points");
}

/// A read-only memory map of a whole file: the body is decoded straight from the page cache
/// instead of being copied into a buffer first (as PCL's own reader does).
class MappedFile {
 public:
  explicit MappedFile(const std::filesystem::path& path) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) throw Error(path.string() + ": no such file");
    if (std::filesystem::is_directory(path, ec))
      throw Error(path.string() + ": is a folder, expected a file");
    fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd_ < 0) throw Error(path.string() + ": cannot open for reading");
    struct stat st {};
    if (::fstat(fd_, &st) != 0) {
      ::close(fd_);
      throw Error(path.string() + ": cannot determine its size");
    }
    size_ = static_cast<std::size_t>(st.st_size);
    if (size_ > 0) {
      void* p = ::mmap(nullptr, size_, PROT_READ, MAP_PRIVATE, fd_, 0);
      if (p == MAP_FAILED) {
        ::close(fd_);
        throw Error(path.string() + ": cannot map the file for reading");
      }
      data_ = static_cast<const std::byte*>(p);
    }
  }
  ~MappedFile() {
    if (data_) ::munmap(const_cast<std::byte*>(data_), size_);
    ::close(fd_);
  }
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;
  std::span<const std::byte> bytes() const { return {data_, size_}; }

 private:
  int fd_ = -1;
  const std::byte* data_ = nullptr;
  std::size_t size_ = 0;
};

}  // namespace

PointCloud parse_pcd(std::span<const std::byte> bytes, const std::string& source) {
  const PcdHeader h = detail::parse_pcd_header(bytes, source);
  // Bounds by division first, so that no product of header numbers can wrap around.
  const std::uint64_t available = bytes.size() - h.data_offset;
  if (h.data_type == 1 && h.points > available / h.point_step)
    detail::pcd_fail(source, "truncated: " + std::to_string(h.points) + " points of " +
                                 std::to_string(h.point_step) + " bytes do not fit in the " +
                                 std::to_string(available) + " bytes that follow the header");
  if (h.data_type == 0 && h.points > available)
    detail::pcd_fail(source, "truncated: " + std::to_string(h.points) +
                                 " points cannot fit in the " + std::to_string(available) +
                                 " bytes of ascii data");
  if (h.data_type == 2 && h.points > UINT32_MAX / h.point_step)
    detail::pcd_fail(source, std::to_string(h.points) + " points of " +
                                 std::to_string(h.point_step) +
                                 " bytes exceed the 4 GiB a binary_compressed body can hold");
  const std::uint64_t data_bytes = h.points * h.point_step;
  if (h.data_type == 2 && h.points > 0) {
    if (available < 8)
      detail::pcd_fail(source, "truncated: binary_compressed data has no size words");
    const std::uint32_t compressed = get_u32(bytes, h.data_offset);
    const std::uint32_t uncompressed = get_u32(bytes, h.data_offset + 4);
    if (uncompressed != data_bytes)
      detail::pcd_fail(source, "binary_compressed data says " + std::to_string(uncompressed) +
                                   " bytes uncompressed, the header needs " +
                                   std::to_string(data_bytes));
    if (compressed > available - 8)
      detail::pcd_fail(source, "truncated: compressed data of " + std::to_string(compressed) +
                                   " bytes, only " + std::to_string(available - 8) + " follow");
  }

  const auto width = static_cast<std::uint32_t>(h.width);
  const auto height = static_cast<std::uint32_t>(h.height);
  if (h.data_type == 0) {
    pcl::PCLPointCloud2 blob;
    std::uint32_t offset = 0;
    for (std::size_t i = 0; i < h.names.size(); ++i) {
      Field f;
      f.name = h.names[i];
      f.offset = offset;
      f.datatype = detail::pcd_pcl_type(h.types[i], h.sizes[i]);
      f.count = h.counts[i];
      offset += h.sizes[i] * h.counts[i];
      blob.fields.push_back(f);
    }
    blob.width = width;
    blob.height = height;
    blob.point_step = static_cast<std::uint32_t>(h.point_step);
    blob.row_step = blob.point_step * blob.width;
    blob.data.resize(data_bytes);
    if (h.points > 0) parse_ascii_body(bytes, h, blob, source);
    PointCloud cloud = detail::from_pcl_cloud2(blob, source);
    cloud.origin_m = detail::pcd_origin(h);
    return cloud;
  }

  // Binary bodies are read in place, without PCL's intermediate point-major copy: `binary` is
  // point-major straight from the file; `binary_compressed` is LZF (PCL's decoder) of field-major
  // planes, each field's n values contiguous, which the conversion reads directly.
  const auto* body = reinterpret_cast<const std::uint8_t*>(bytes.data()) + h.data_offset;
  std::unique_ptr<std::uint8_t[]> planes;
  if (h.data_type == 2 && h.points > 0) {
    planes.reset(new std::uint8_t[data_bytes]);
    const unsigned got = pcl::lzfDecompress(body + 8, get_u32(bytes, h.data_offset), planes.get(),
                                            static_cast<unsigned>(data_bytes));
    if (got != data_bytes)
      detail::pcd_fail(source, "corrupt binary_compressed data (LZF decoded " +
                                   std::to_string(got) + " of " + std::to_string(data_bytes) +
                                   " bytes)");
  }
  std::vector<detail::FieldView> views;
  std::uint64_t offset = 0;
  for (std::size_t i = 0; i < h.names.size(); ++i) {
    detail::FieldView v;
    v.name = h.names[i];
    v.datatype = detail::pcd_pcl_type(h.types[i], h.sizes[i]);
    if (h.data_type == 1) {
      v.base = body + offset;
      v.stride = h.point_step;
    } else {
      v.base = planes.get() + h.points * offset;
      v.stride = std::size_t(h.sizes[i]) * h.counts[i];
    }
    offset += std::uint64_t(h.sizes[i]) * h.counts[i];
    views.push_back(std::move(v));
  }
  PointCloud cloud = detail::from_field_views(views, width, height, source);
  cloud.origin_m = detail::pcd_origin(h);
  return cloud;
}

PointCloud read_pcd(const std::filesystem::path& path) {
  const MappedFile file(path);
  return parse_pcd(file.bytes(), path.string());
}

}  // namespace fieldlidar::io
