// Every writer goes through check_writable and write_file_atomic: a failed write throws and
// leaves no file, and no output replaces a special file or an input.

#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/kitti_bin.hpp"
#include "fieldlidar/io/label_file.hpp"
#include "fieldlidar/io/pcd.hpp"
#include "fieldlidar/io/ply.hpp"
#include "fieldlidar/io/trajectory_io.hpp"
#include "test_data.hpp"

namespace fieldlidar {
namespace {

namespace fs = std::filesystem;

PointCloud big_cloud() {
  PointCloud c;
  c.fields.intensity = true;
  for (int i = 0; i < 20000; ++i) c.push_back({0.001f * i, 2.f, -1.f, float(i % 100)});
  return c;
}

/// Runs `write` in a child process whose files may not exceed 4 KiB (as on a full disk): the
/// child exits 0 when the write threw fieldlidar::Error saying "write failed", 2 when it did not
/// throw, 3 on another error.
int write_with_size_limit(const std::function<void()>& write) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::signal(SIGXFSZ, SIG_IGN);
    const rlimit limit{4096, 4096};
    ::setrlimit(RLIMIT_FSIZE, &limit);
    try {
      write();
    } catch (const Error& e) {
      ::_exit(std::string(e.what()).find("write failed") != std::string::npos ? 0 : 3);
    } catch (...) {
      ::_exit(3);
    }
    ::_exit(2);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(FileUtil, FailedWritesThrowAndLeaveNoFile) {
  const auto c = big_cloud();  // 20000 points: 320 kB as KITTI .bin
  Trajectory t;
  for (int i = 0; i < 2000; ++i) t.push_back(0.1 * i, Pose::Identity());
  const std::vector<std::uint32_t> labels(20000, 7);
  const auto dir = test::temp_dir("file_util_full");
  const std::vector<std::pair<std::string, std::function<void()>>> writers = {
      {"ply binary", [&] { io::write_ply(dir / "x.ply", c); }},
      {"ply ascii", [&] { io::write_ply(dir / "x.ply", c, {.binary = false}); }},
      {"pcd binary", [&] { io::write_pcd(dir / "x.pcd", c); }},
      {"pcd ascii", [&] { io::write_pcd(dir / "x.pcd", c, {.binary = false}); }},
      {"pcd compressed", [&] { io::write_pcd(dir / "x.pcd", c, {.compressed = true}); }},
      {"kitti bin", [&] { io::write_kitti_bin(dir / "x.bin", c); }},
      {"labels", [&] { io::write_labels(dir / "x.label", labels); }},
      {"kitti poses", [&] { io::write_kitti_poses(dir / "poses.txt", t); }},
      {"tum", [&] { io::write_tum(dir / "poses_tum.txt", t); }},
  };
  for (const auto& [what, write] : writers) {
    EXPECT_EQ(write_with_size_limit(write), 0) << what;
    std::string left;
    for (const auto& e : fs::directory_iterator(dir)) left += e.path().filename().string() + " ";
    EXPECT_TRUE(left.empty()) << what << " left " << left;
  }
  // Without the limit the same writes succeed and leave exactly their file.
  io::write_ply(dir / "x.ply", c);
  EXPECT_EQ(io::read_ply(dir / "x.ply").size(), c.size());
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
}

TEST(FileUtil, CheckWritableRefusesSpecialFilesAndInputs) {
  const auto dir = test::temp_dir("file_util_check");
  const auto regular = dir / "a.bin", fifo = dir / "fifo.bin", link = dir / "link.bin",
             hard = dir / "hard.bin";
  { std::ofstream(regular) << "data"; }
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  fs::create_symlink(regular, link);
  fs::create_hard_link(regular, hard);
  EXPECT_THROW(io::check_writable(regular, false), Error);  // exists, no overwrite
  EXPECT_NO_THROW(io::check_writable(regular, true));
  EXPECT_NO_THROW(io::check_writable(dir / "new.bin", false, {regular}));
  for (const auto& p : {fifo, link, dir}) EXPECT_THROW(io::check_writable(p, true), Error) << p;
  EXPECT_THROW(io::check_writable(regular, true, {regular}), Error);
  EXPECT_THROW(io::check_writable(hard, true, {regular}), Error);  // same inode, other name
  EXPECT_THROW(io::check_writable(dir / "no" / "x.bin", true), Error);
  try {
    io::check_writable(fifo, true);
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("FIFO"), std::string::npos) << e.what();
  }
  // The writers refuse them too and leave them as they were.
  EXPECT_THROW(io::write_labels(fifo, std::vector<std::uint32_t>{1, 2}, {.overwrite = true}),
               Error);
  EXPECT_THROW(io::write_labels(link, std::vector<std::uint32_t>{1, 2}, {.overwrite = true}),
               Error);
  EXPECT_TRUE(fs::is_fifo(fs::symlink_status(fifo)));
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(link)));
  EXPECT_EQ(fs::file_size(regular), 4u);
}

}  // namespace
}  // namespace fieldlidar
