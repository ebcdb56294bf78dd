// End to end: the clock of a folder of frames for the commands that track people over time
// (legs, follow --replay): a simulator folder's times.txt stamps its pcd/, frames without a
// clock are refused (before, every track ever seen lived on and the run slowed without bound),
// `--rate` gives them one. And the rough lawn of `simulate --rough`, whose scripted mower
// tilts on the bumps.

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "fieldlidar/io/trajectory_io.hpp"
#include "run_cli.hpp"
#include "test_data.hpp"

namespace fieldlidar {
namespace {

namespace fs = std::filesystem;

/// The distinct stamps of a `legs --out` CSV.
std::set<std::string> csv_stamps(const fs::path& csv) {
  std::ifstream in(csv);
  std::set<std::string> stamps;
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) stamps.insert(line.substr(0, line.find(',')));
  return stamps;
}

TEST(CliFrameClock, FramesWithoutAClockAreRefusedAndRateGivesThemOne) {
  const auto dir = test::temp_dir("cli_frame_clock");
  auto r = test::run_cli("simulate --scene lawn --sensor laser2d --frames 40 --out " +
                         test::quoted(dir / "sim"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // The simulator folder's pcd/ lies beside its times.txt: 0.1 s apart.
  const auto csv = dir / "legs.csv";
  r = test::run_cli("legs " + test::quoted(dir / "sim" / "pcd") + " --out " + test::quoted(csv));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_GT(csv_stamps(csv).size(), 20u);  // the operator's legs in most of the 40 scans
  EXPECT_EQ(csv_stamps(csv).count("3.900000"), 1u);
  // The same files without it: all stamped 0.
  fs::create_directories(dir / "bare");
  fs::copy(dir / "sim" / "pcd", dir / "bare" / "pcd");
  r = test::run_cli("legs " + test::quoted(dir / "bare" / "pcd") + " --out " +
                    test::quoted(dir / "bare.csv"));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("10 frames in a row carry the same stamp (0.000000 s)"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("legs --rate HZ"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "bare.csv"));
  r = test::run_cli("follow --replay " + test::quoted(dir / "bare" / "pcd") + " --out " +
                    test::quoted(dir / "replay"));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("times.txt in or beside it"), std::string::npos) << r.output;
  r = test::run_cli("follow --replay " + test::quoted(dir / "bare" / "pcd") + " --rate 10 --out " +
                    test::quoted(dir / "replay"));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("40 frames (3.9 s)"), std::string::npos) << r.output;
  r = test::run_cli("legs " + test::quoted(dir / "bare" / "pcd") + " --rate 10 --out " +
                    test::quoted(dir / "bare.csv"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(csv_stamps(dir / "bare.csv"), csv_stamps(csv));
}

TEST(CliFrameClock, RoughLawnTiltsTheScriptedMower) {
  const auto dir = test::temp_dir("cli_rough_lawn");
  const auto max_tilt_deg = [&](const std::string& options) {
    const auto out = dir / (options.empty() ? "mown" : "rough");
    const auto r = test::run_cli("simulate --scene lawn --sensor laser2d --frames 60 " + options +
                                 " --out " + test::quoted(out));
    EXPECT_EQ(r.exit_code, 0) << r.output;
    double tilt = 0;
    for (const auto& p : io::read_tum(out / "poses_tum.txt"))
      tilt = std::max(tilt, std::acos(std::clamp(p.pose.rotation()(2, 2), -1.0, 1.0)));
    return tilt * 180.0 / M_PI;
  };
  // Measured 1.1 deg on the mown lawn's gentle waves, 7.7 deg on 6 cm bumps (first 6 s).
  const double mown = max_tilt_deg(""), rough = max_tilt_deg("--rough 0.06");
  EXPECT_LT(mown, 2.0);
  EXPECT_GT(rough, 4.0);
  EXPECT_LT(rough, 12.0);
  const auto r =
      test::run_cli("simulate --scene lawn --rough 0.5 --out " + test::quoted(dir / "bad"));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("--rough"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace fieldlidar
