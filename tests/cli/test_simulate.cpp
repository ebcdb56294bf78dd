// fieldlidar simulate end to end: the files it writes, their agreement, and its refusals.

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "fieldlidar/io/cloud_file.hpp"
#include "fieldlidar/io/label_file.hpp"
#include "fieldlidar/io/trajectory_io.hpp"
#include "run_cli.hpp"
#include "test_data.hpp"

namespace fieldlidar {
namespace {

namespace fs = std::filesystem;

std::size_t count_lines(const fs::path& p) {
  std::ifstream in(p);
  std::size_t n = 0;
  for (std::string line; std::getline(in, line);) n += !line.empty();
  return n;
}

TEST(CliSimulate, LawnWritesFramesTruthAndPreview) {
  const auto dir = test::temp_dir("simulate_lawn");
  const auto r = test::run_cli("simulate --scene lawn --frames 3 --seed 4 --crossing --out " +
                               dir.string() + " --preview");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("lawn scene"), std::string::npos);
  for (int i = 0; i < 3; ++i) {
    const std::string name = "00000" + std::to_string(i);
    const auto bin = io::read_cloud(dir / "velodyne" / (name + ".bin"));
    const auto labels = io::read_labels(dir / "labels" / (name + ".label"), bin.size());
    const auto pcd = io::read_cloud(dir / "pcd" / (name + ".pcd"));
    ASSERT_GT(bin.size(), 5000u);
    EXPECT_EQ(pcd.size(), bin.size());
    EXPECT_TRUE(pcd.has_labels());
    EXPECT_EQ(pcd.labels, labels);
    EXPECT_EQ(pcd.ring_count(), 16u);
    EXPECT_NEAR(pcd.points.back().x, bin.points.back().x, 1e-5);
  }
  const auto poses = io::read_kitti_poses(dir / "poses.txt", dir / "times.txt");
  ASSERT_EQ(poses.size(), 3u);
  EXPECT_NEAR(poses[1].stamp_s, 0.1, 1e-9);
  EXPECT_NEAR(poses[0].pose.translation().z(), 0.45, 0.15);  // mower lidar height above the lawn
  EXPECT_EQ(count_lines(dir / "people.csv"), 1u + 3u * 2u);  // header + 2 people per frame
  EXPECT_GT(count_lines(dir / "imu.csv"), 55u);              // 200 Hz over 0.3 s
  EXPECT_GT(count_lines(dir / "odom.csv"), 14u);             // 50 Hz
  EXPECT_GT(count_lines(dir / "operator_path.csv"), 10u);
  std::ifstream png(dir / "preview.png", std::ios::binary);
  char sig[8] = {};
  png.read(sig, 8);
  EXPECT_EQ(std::string(sig + 1, 3), "PNG");

  // A second run into the same folder must not replace anything without --force.
  const auto again = test::run_cli("simulate --scene lawn --frames 1 --out " + dir.string());
  EXPECT_EQ(again.exit_code, 1);
  EXPECT_NE(again.output.find("--force"), std::string::npos) << again.output;
  const auto forced =
      test::run_cli("simulate --scene lawn --frames 1 --out " + dir.string() + " --force");
  EXPECT_EQ(forced.exit_code, 0) << forced.output;
}

TEST(CliSimulate, ForestAndTerrainWriteTheirTruth) {
  const auto forest = test::temp_dir("simulate_forest");
  ASSERT_EQ(test::run_cli("simulate --scene forest --frames 1 --out " + forest.string()).exit_code,
            0);
  EXPECT_GT(count_lines(forest / "trees.csv"), 20u);
  const auto terrain = test::temp_dir("simulate_terrain");
  const auto r = test::run_cli("simulate --scene terrain --frames 1 --truth-resolution 0.5 --out " +
                               terrain.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream pgm(terrain / "terrain_truth.pgm", std::ios::binary);
  std::string magic, comment;
  int w = 0, h = 0, maxval = 0;
  pgm >> magic;
  pgm.ignore(1);
  std::getline(pgm, comment);
  pgm >> w >> h >> maxval;
  EXPECT_EQ(magic, "P5");
  EXPECT_EQ(w, 121);  // 60 m / 0.5 m, plus the cell holding the far edge
  EXPECT_EQ(h, 81);
  EXPECT_EQ(maxval, 255);
  std::ifstream yaml(terrain / "terrain_truth.yaml");
  std::stringstream ss;
  ss << yaml.rdbuf();
  EXPECT_NE(ss.str().find("resolution: 0.5"), std::string::npos);
  EXPECT_NE(ss.str().find("image: terrain_truth.pgm"), std::string::npos);
  const auto greenhouse = test::temp_dir("simulate_greenhouse");
  EXPECT_EQ(test::run_cli("simulate --scene greenhouse --sensor hdl32e --frames 1 --out " +
                          greenhouse.string())
                .exit_code,
            0);
  EXPECT_EQ(io::read_cloud(greenhouse / "pcd" / "000000.pcd").ring_count(), 32u);
}

TEST(CliSimulate, RejectsBadArguments) {
  const auto dir = test::temp_dir("simulate_bad");
  auto r = test::run_cli("simulate --scene moon --out " + dir.string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("unknown scene 'moon'"), std::string::npos) << r.output;
  r = test::run_cli("simulate --scene lawn --sensor lidar9000 --out " + dir.string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("lidar9000"), std::string::npos);
  r = test::run_cli("simulate --scene lawn --frames 0 --out " + dir.string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("--frames"), std::string::npos);
}

// A run larger than the disk under its folder is refused after one sweep is simulated, before
// anything is written: 100,000 OS2-128 sweeps of the terrain scene, about 190 GB.
TEST(CliSimulate, RunLargerThanTheDiskIsRefusedBeforeWriting) {
  const auto dir = test::temp_dir("simulate_disk");
  std::error_code ec;
  const auto space = fs::space(dir, ec);
  if (ec || space.available > 150'000'000'000ull)
    GTEST_SKIP() << "the disk holds more than 150 GB free: the run would fit";
  const auto out = dir / "big";
  const auto r = test::run_cli("simulate --scene terrain --sensor os2-128 --frames 100000 --out " +
                               test::quoted(out));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("GB free; simulate fewer frames"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace fieldlidar
