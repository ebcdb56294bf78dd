// FrameSource over cloud files: single file, folder and glob in name order; dispatch errors.
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/cloud_file.hpp"
#include "fieldlidar/io/frame_source.hpp"
#include "fieldlidar/io/kitti_bin.hpp"
#include "test_data.hpp"

namespace fieldlidar {
namespace {

void write_bin(const std::filesystem::path& p, float x, std::size_t n) {
  PointCloud c;
  for (std::size_t i = 0; i < n; ++i) {
    Point q;
    q.x = x;
    q.y = float(i);
    c.push_back(q);
  }
  io::write_kitti_bin(p, c);
}

TEST(FrameSource, FolderAndGlobIterateInNameOrder) {
  const auto dir = test::temp_dir("frame_source_folder");
  write_bin(dir / "b_002.bin", 2, 3);
  write_bin(dir / "b_000.bin", 0, 1);
  write_bin(dir / "b_001.bin", 1, 2);
  write_bin(dir / "other.bin", 9, 4);
  std::ofstream(dir / "notes.txt") << "not a cloud";
  auto src = io::FrameSource::open(dir);
  EXPECT_EQ(src->format(), "kitti-bin");
  std::vector<float> xs;
  while (auto f = src->next()) {
    EXPECT_EQ(f->index, xs.size());
    xs.push_back(f->cloud.points[0].x);
  }
  EXPECT_EQ(xs, (std::vector<float>{0, 1, 2, 9}));
  EXPECT_DOUBLE_EQ(src->progress(), 1.0);
  auto glob = io::FrameSource::open(dir / "b_*.bin");
  std::vector<std::size_t> sizes;
  while (auto f = glob->next()) sizes.push_back(f->cloud.size());
  EXPECT_EQ(sizes, (std::vector<std::size_t>{1, 2, 3}));
  EXPECT_THROW(io::FrameSource::open(dir / "zzz_*.bin"), Error);
}

// A sequence folder's clock: KITTI's times.txt beside velodyne/ (and a simulator's beside pcd/), or
// one inside the folder; one that lists another number of frames is named and not used.
TEST(FrameSource, FolderFramesAreStampedByTheSequencesTimesFile) {
  const auto seq = test::temp_dir("frame_source_times");
  const auto dir = seq / "velodyne";
  std::filesystem::create_directories(dir);
  for (int k = 0; k < 3; ++k) write_bin(dir / ("00000" + std::to_string(k) + ".bin"), k, 1);
  const auto stamps = [](const std::filesystem::path& p, std::vector<std::string>* warnings) {
    auto src = io::FrameSource::open(p);
    std::vector<double> out;
    while (auto f = src->next()) {
      EXPECT_DOUBLE_EQ(f->stamp_s, f->cloud.stamp_s);
      out.push_back(f->stamp_s);
    }
    if (warnings) *warnings = src->warnings();
    return out;
  };
  EXPECT_EQ(stamps(dir, nullptr), (std::vector<double>{0, 0, 0}));  // no clock: the files' own
  std::ofstream(seq / "times.txt") << "0.0\n0.103\n0.2\n";
  EXPECT_EQ(stamps(dir, nullptr), (std::vector<double>{0, 0.103, 0.2}));
  std::ofstream(dir / "times.txt") << "1\n2\n";  // the folder's own comes first
  std::vector<std::string> warnings;
  EXPECT_EQ(stamps(dir, &warnings), (std::vector<double>{0, 0, 0}));
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("lists 2 stamps for 3 frame files"), std::string::npos) << warnings[0];
  std::ofstream(dir / "times.txt") << "1\nnot a time\n3\n";
  EXPECT_EQ(stamps(dir, &warnings), (std::vector<double>{0, 0, 0}));
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("not used as the frames' clock"), std::string::npos) << warnings[0];
}

// A simulator's output folder (pcd/ beside velodyne/ and times.txt) and a KITTI sequence folder
// (velodyne/ and times.txt) open as their frames; a folder with frames of its own is read as it
// is, and one with neither names what it lacks.
TEST(FrameSource, SequenceFolderOpensAsItsFramesSubfolder) {
  const auto seq = test::temp_dir("frame_source_sequence");
  std::filesystem::create_directories(seq / "velodyne");
  for (int k = 0; k < 2; ++k)
    write_bin(seq / "velodyne" / ("00000" + std::to_string(k) + ".bin"), k, 2);
  std::ofstream(seq / "times.txt") << "0.5\n0.6\n";
  const auto read = [](const std::filesystem::path& p) {
    auto src = io::FrameSource::open(p);
    std::vector<std::pair<std::size_t, double>> out;
    while (auto f = src->next()) out.push_back({f->cloud.size(), f->stamp_s});
    return std::pair(src->format(), out);
  };
  using Frames = std::vector<std::pair<std::size_t, double>>;
  EXPECT_EQ(read(seq), std::pair(std::string("kitti-bin"), Frames{{2, 0.5}, {2, 0.6}}));
  std::filesystem::create_directories(seq / "pcd");  // a simulator folder: its PCD frames first
  PointCloud c;
  c.points.resize(3);
  for (int k = 0; k < 2; ++k)
    io::write_cloud(seq / "pcd" / ("00000" + std::to_string(k) + ".pcd"), c);
  EXPECT_EQ(read(seq), std::pair(std::string("pcd"), Frames{{3, 0.5}, {3, 0.6}}));
  write_bin(seq / "own.bin", 9, 1);  // frames of its own: those
  EXPECT_EQ(read(seq).second, (Frames{{1, 0}}));
  const auto empty = test::temp_dir("frame_source_sequence_empty");
  try {
    io::FrameSource::open(empty);
    ADD_FAILURE() << "an empty folder opened";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no .bin, .pcd, .ply or .las files"), std::string::npos);
  }
}

TEST(FrameSource, SingleKittiFile) {
  FIELDLIDAR_REQUIRE_DATA("kitti00/000000.bin");
  auto src = io::FrameSource::open(test::data_file("kitti00/000000.bin"));
  const auto f = src->next();
  ASSERT_TRUE(f);
  EXPECT_GT(f->cloud.size(), 100000u);
  EXPECT_FALSE(src->next());
  EXPECT_TRUE(src->imu_until(1e18).empty());
}

TEST(FrameSource, UnknownInputsGiveClearErrors) {
  const auto dir = test::temp_dir("frame_source_errors");
  EXPECT_THROW(io::FrameSource::open(dir / "missing.pcap"), Error);
  std::ofstream(dir / "x.txt") << "text";
  EXPECT_THROW(io::FrameSource::open(dir / "x.txt"), Error);
  std::ofstream(dir / "junk.pcap") << "not a capture at all";
  EXPECT_THROW(io::FrameSource::open(dir / "junk.pcap"), Error);
  std::ofstream(dir / "junk.bag") << "not a bag";
  EXPECT_THROW(io::FrameSource::open(dir / "junk.bag"), Error);
}

TEST(FrameSource, OusterCaptureWithoutMetadataSaysHowToGiveIt) {
  FIELDLIDAR_REQUIRE_DATA("ouster_pcap/OS-1-64_1024x10_fw20.pcap");
  try {
    io::FrameSource::open(test::data_file("ouster_pcap/OS-1-64_1024x10_fw20.pcap"));
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("--metadata"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace fieldlidar
