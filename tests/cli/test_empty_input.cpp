// End-to-end: inputs without a point, and results without anything in them. Commands with
// nothing to work on fail naming the input (exit status 1); a map that came out without a known
// cell is written, with a warning saying why that may be.

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "run_cli.hpp"
#include "test_data.hpp"

namespace fieldlidar {
namespace {

namespace fs = std::filesystem;

/// A KITTI .bin of `points` (x, y, z, intensity each).
void write_bin(const fs::path& path, const std::vector<float>& points) {
  std::ofstream f(path, std::ios::binary);
  f.write(reinterpret_cast<const char*>(points.data()),
          static_cast<std::streamsize>(points.size() * sizeof(float)));
}

TEST(CliEmptyInput, CommandsWithoutAPointFailNamingTheInput) {
  const auto dir = test::temp_dir("cli_empty_input");
  const auto empty = dir / "empty.bin";
  write_bin(empty, {});
  { std::ofstream(dir / "empty.label", std::ios::binary); }
  const std::string in = test::quoted(empty);
  const struct {
    std::string args, message;
  } cases[] = {
      {"convert " + in + " " + test::quoted(dir / "c.pcd"), "has no points: nothing to convert"},
      {"legs " + in + " --out " + test::quoted(dir / "legs.csv"),
       "holds no points: no legs to look for"},
      {"odometry " + in + " --sensor vlp16 -o " + test::quoted(dir / "odo"),
       "holds no points: nothing to register"},
      {"trunks " + in + " --out " + test::quoted(dir / "trunks"),
       "holds no points: no trunks to look for"},
      {"eval-people3d " + in + " --sensor vlp16 --point-labels " +
           test::quoted(dir / "empty.label"),
       "holds no points: no person to detect"},
  };
  for (const auto& c : cases) {
    const auto r = test::run_cli(c.args);
    EXPECT_EQ(r.exit_code, 1) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find("fieldlidar: error: " + empty.string() + ": " + c.message),
              std::string::npos)
        << c.args << "\n"
        << r.output;
  }
  EXPECT_FALSE(fs::exists(dir / "c.pcd"));
  EXPECT_FALSE(fs::exists(dir / "legs.csv"));
  EXPECT_FALSE(fs::exists(dir / "odo" / "poses.txt"));
  EXPECT_FALSE(fs::exists(dir / "trunks" / "trees.csv"));
}

// A command refused for its input after making its output folder takes the folder away again:
// no empty folder is left where the user asked for results.
TEST(CliEmptyInput, RefusedRunsLeaveNoEmptyOutputFolder) {
  const auto dir = test::temp_dir("cli_refused_folders");
  const auto frames = dir / "frames";
  fs::create_directories(frames);  // a folder of no frame file
  const std::string in = test::quoted(frames);
  const struct {
    std::string args, out;
  } cases[] = {
      {"traversability " + in + " --out " + test::quoted(dir / "t"), "t"},
      {"trunks " + in + " --out " + test::quoted(dir / "tr"), "tr"},
      {"odometry " + in + " --out " + test::quoted(dir / "o"), "o"},
      {"plan --map " + in + " --start 1,1,0 --goal 2,2,0 --out " + test::quoted(dir / "p"), "p"},
      {"navigate --goal 100,1,0 --out " + test::quoted(dir / "n"), "n"},
      {"navigate --pairs " + test::quoted(dir / "pairs.csv") + " --out " + test::quoted(dir / "np"),
       "np"},
  };
  std::ofstream(dir / "pairs.csv") << "far,3,20,0,100,20,0\n";  // a goal off the scene
  for (const auto& c : cases) {
    const auto r = test::run_cli(c.args);
    EXPECT_EQ(r.exit_code, 1) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find("fieldlidar: error: "), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir / c.out)) << c.args;
  }
}

// A capture shorter than one sweep gives no frame: an error saying why, and no folder left.
TEST(CliEmptyInput, CaptureWithoutACompleteSweepConvertsToNothing) {
  const std::string name = "velodyne_pcap/hdl32_example.pcap";
  FIELDLIDAR_REQUIRE_DATA(name);
  const auto dir = test::temp_dir("cli_empty_capture");
  const auto cut = dir / "cut.pcap";
  {
    std::ifstream in(test::data_file(name), std::ios::binary);
    std::vector<char> head(106200);  // the ends of two sweeps, neither whole
    in.read(head.data(), static_cast<std::streamsize>(head.size()));
    std::ofstream(cut, std::ios::binary).write(head.data(), in.gcount());
  }
  const auto r = test::run_cli("convert -q " + test::quoted(cut) + " " + test::quoted(dir / "out"));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("fieldlidar: error: " + cut.string() +
                          ": no frame to convert (only 2 partial sweeps: --partial writes them)"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(dir / "out"));
}

TEST(CliEmptyInput, MapWithoutAKnownCellIsWrittenWithAWarning) {
  const auto dir = test::temp_dir("cli_empty_map");
  const auto one = dir / "one.bin";
  write_bin(one, {3, 1, -1.5f, 0.2f});
  const auto r = test::run_cli("traversability " + test::quoted(one) + " --sensor vlp16 --out " +
                               test::quoted(dir / "map"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("fieldlidar: warning: " + one.string() + ": no cell of the"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("try a larger --cell"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("no --sensor if the input is a survey"), std::string::npos) << r.output;
  EXPECT_TRUE(fs::exists(dir / "map" / "traversability.yaml"));
}

// More poses than frames are the poses of another sequence: refused as fewer are.
TEST(CliEmptyInput, PosesBeyondTheFramesAreAnError) {
  const auto dir = test::temp_dir("cli_extra_poses");
  fs::create_directories(dir / "frames");
  for (const char* name : {"000000.bin", "000001.bin"})
    write_bin(dir / "frames" / name, {3, 1, -1.5f, 0.2f, 4, -1, -1.5f, 0.2f});
  std::ofstream poses(dir / "poses.txt");
  for (int i = 0; i < 3; ++i) poses << "1 0 0 " << i << " 0 1 0 0 0 0 1 0\n";
  poses.close();
  const auto r =
      test::run_cli("traversability " + test::quoted(dir / "frames") + " --sensor vlp16 --poses " +
                    test::quoted(dir / "poses.txt") + " --out " + test::quoted(dir / "map"));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("fieldlidar: error: --poses " + (dir / "poses.txt").string() +
                          ": 3 poses for the 2 frames of"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(dir / "map" / "traversability.yaml"));
}

}  // namespace
}  // namespace fieldlidar
