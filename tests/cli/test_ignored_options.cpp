// End-to-end: options a command would not use are refused naming the option, rather than
// ignored; so are values the command line alone shows to be wrong (duplicate pair names, a
// missing data folder given explicitly). Every case fails before any output is written.

#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "run_cli.hpp"
#include "test_data.hpp"

namespace fieldlidar {
namespace {

namespace fs = std::filesystem;

TEST(CliIgnoredOptions, ConvertRefusesWhatItWouldIgnore) {
  const auto dir = test::temp_dir("cli_convert_options");
  const float point[4] = {1, 2, 3, 0.5f};
  fs::create_directories(dir / "frames");
  for (const auto& f : {dir / "small.bin", dir / "frames" / "000000.bin"})
    std::ofstream(f, std::ios::binary).write(reinterpret_cast<const char*>(point), sizeof point);
  const std::string in = test::quoted(dir / "small.bin");
  const auto out = [&](const char* name) { return " " + test::quoted(dir / "out" / name); };
  fs::create_directories(dir / "out");
  const struct {
    std::string args, message;
  } cases[] = {
      {in + out("a.bin") + " --compressed",
       "--compressed: only PCD has a binary_compressed encoding; the output format is kitti-bin"},
      {in + out("a.ply") + " --compressed", "--compressed: only PCD has"},
      {in + out("a.bin") + " --ascii", "--ascii: KITTI .bin has no ASCII encoding"},
      {in + out("a.pcd") + " --ascii --compressed", "--compressed: and --ascii exclude each other"},
      {in + out("a.ply") + " --format bin", "--format: sets the format of the frame files"},
      {in + out("a.xyz"),
       "a.xyz: unknown output extension '.xyz': a cloud is written as .pcd, "
       ".ply or .bin"},
      {test::quoted(dir / "frames") + out("a.pcd"),
       "a.pcd: names one cloud file, but " + (dir / "frames").string() +
           " is a sequence of frames: give an output folder"},
      {test::quoted(dir / "frames") + out("f") + " --format bin --ascii",
       "--ascii: KITTI .bin has no ASCII encoding"},
  };
  for (const auto& c : cases) {
    const auto r = test::run_cli("convert " + c.args);
    EXPECT_EQ(r.exit_code, 1) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find("fieldlidar: error: "), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(c.message), std::string::npos) << c.args << "\n" << r.output;
  }
  EXPECT_TRUE(fs::is_empty(dir / "out"));
  // What they allow still works: a folder without an extension, --format for it.
  const auto r = test::run_cli("convert " + in + out("f") + " --format bin");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(dir / "out" / "f" / "000000.bin"));
}

TEST(CliIgnoredOptions, LegsTrainClassifierNeedsNegativesAndKnownFeatures) {
  const auto dir = test::temp_dir("cli_legs_train_options");
  const std::string out = " --out " + test::quoted(dir / "legs.yaml");
  auto r = test::run_cli("legs-train --positive x.bag --classifier" + out);
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("fieldlidar: error: --classifier: the leg classifier learns from scans "
                          "without people too: give --negative bags"),
            std::string::npos)
      << r.output;
  r = test::run_cli("legs-train --positive x.bag --exclude-features range_m bogus" + out);
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("fieldlidar: error: --exclude-features: 'bogus' is not a segment "
                          "feature (points, chord_m, "),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(dir / "legs.yaml"));
}

TEST(CliIgnoredOptions, SimulateRefusesLawnSettingsForOtherScenes) {
  const auto dir = test::temp_dir("cli_simulate_options");
  for (const std::string option : {"--rough 0.06", "--crossing", "--extra-walkers 2"}) {
    const auto r = test::run_cli("simulate --scene terrain --frames 1 " + option + " --out " +
                                 test::quoted(dir / "sim"));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_NE(r.output.find("fieldlidar: error: " + option.substr(0, option.find(' ')) +
                            ": a lawn scenario setting; --scene terrain has no operator or lawn"),
              std::string::npos)
        << r.output;
  }
  EXPECT_FALSE(fs::exists(dir / "sim"));
}

// The simulated follow loop has no recording: the replay's options are refused without
// --replay (they were ignored, and the loop ran on the simulator as if they had not been given).
TEST(CliIgnoredOptions, FollowRefusesReplayOptionsWithoutAReplay) {
  const auto dir = test::temp_dir("cli_follow_options");
  for (const std::string option : {"--topic /scan", "--odom /odom", "--rate 10"}) {
    const auto r = test::run_cli("follow " + option + " --out " + test::quoted(dir / "f"));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_NE(r.output.find("fieldlidar: error: " + option.substr(0, option.find(' ')) +
                            " requires --replay"),
              std::string::npos)
        << r.output;
  }
  EXPECT_FALSE(fs::exists(dir / "f"));
}

TEST(CliIgnoredOptions, NavigateAndPlanArgumentsAreCheckedUpFront) {
  const auto dir = test::temp_dir("cli_navigate_options");
  std::ofstream(dir / "pairs.csv") << "a,-20,0,0,20,0,0\nb,-20,5,0,20,5,0\na,-20,-5,0,20,-5,0\n";
  const std::string out = " --out " + test::quoted(dir / "nav");
  const struct {
    std::string args, message;
  } cases[] = {
      {"navigate --pairs " + test::quoted(dir / "pairs.csv") + out,
       "--pairs " + (dir / "pairs.csv").string() + ": two pairs are named 'a'"},
      {"navigate --sensor tilting2d" + out,
       "--sensor: 'tilting2d' is not a multi-beam preset (vlp16, vlp32c, hdl32e, hdl64e, os1-64, "
       "os1-128, os2-128)"},
      {"navigate --guess-looks 1.5" + out,
       "--guess-looks: must be a whole number in [0, 20], got '1.5'"},
      {"navigate --guess-looks 21" + out, "--guess-looks: must be a whole number in [0, 20]"},
      {"plan --map m.yaml --start 0,0,0 --goal 1,1,0 --late-expansions -1" + out,
       "--late-expansions: must be a whole number in [0, 100000000], got '-1'"},
  };
  for (const auto& c : cases) {
    const auto r = test::run_cli(c.args);
    EXPECT_EQ(r.exit_code, 1) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find("fieldlidar: error: " + c.message), std::string::npos) << c.args << "\n"
                                                                                   << r.output;
  }
  EXPECT_FALSE(fs::exists(dir / "nav"));
  // The help names the presets the check takes.
  const auto help = test::run_cli("navigate --help");
  EXPECT_NE(help.output.find("a multi-beam preset (vlp16, vlp32c, hdl32e, hdl64e, os1-64,"),
            std::string::npos);
}

TEST(CliIgnoredOptions, DemoRefusesADataFolderGivenWithoutTheScan) {
  const auto dir = test::temp_dir("cli_demo_data");
  const auto r = test::run_cli("demo --data-dir " + test::quoted(dir / "nonexistent") + " --out " +
                               test::quoted(dir / "demo"));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(
      r.output.find("fieldlidar: error: --data-dir " + (dir / "nonexistent").string() + ": " +
                    (dir / "nonexistent" / "rellis3d" / "000001.bin").string() + " does not exist"),
      std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(dir / "demo"));
}

}  // namespace
}  // namespace fieldlidar
