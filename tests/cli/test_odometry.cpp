// fieldlidar odometry on a short simulated greenhouse folder: outputs, overwrite refusal, and
// localisation in the map it wrote.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "run_cli.hpp"
#include "test_data.hpp"

namespace fieldlidar {
namespace {

TEST(CliOdometry, SimulatorFolderWritesPosesMapAndSummary) {
  const auto dir = test::temp_dir("cli_odometry");
  const auto sim = dir / "sim", out = dir / "out", loc = dir / "loc";
  auto r = test::run_cli("simulate --scene greenhouse --frames 15 --out " + sim.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = test::run_cli("odometry " + sim.string() + " --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* f : {"poses.txt", "poses_tum.txt", "map.pcd", "map.png", "summary.json"})
    EXPECT_TRUE(std::filesystem::exists(out / f)) << f;
  std::ifstream in(out / "summary.json");
  std::stringstream ss;
  ss << in.rdbuf();
  const auto s = nlohmann::json::parse(ss.str());
  EXPECT_EQ(s["frames"].get<int>(), 15);
  EXPECT_EQ(s["unregistered_frames"].get<int>(), 0);
  EXPECT_GT(s["map_points"].get<int>(), 1000);
  // Never overwrites without --force.
  r = test::run_cli("odometry " + sim.string() + " --out " + out.string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("exists"), std::string::npos) << r.output;
  // Localisation in the saved map.
  r = test::run_cli("odometry " + sim.string() + " --map-in " + (out / "map.pcd").string() +
                    " --initial-pose 0.3 0 0 0 0 5 --out " + loc.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
}

// --solver ceres solves the same problem: the same trajectory to the file's 7 digits' worth.
TEST(CliOdometry, SolverCeresGivesTheSamePoses) {
  const auto dir = test::temp_dir("cli_odometry_solver");
  const auto sim = dir / "sim";
  auto r = test::run_cli("simulate --scene greenhouse --frames 6 --out " + sim.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = test::run_cli("odometry " + sim.string() + " --solver gauss_newton --out " +
                    (dir / "x").string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("--solver"), std::string::npos) << r.output;
  std::vector<std::vector<double>> poses[2];
  for (int i = 0; i < 2; ++i) {
    const auto out = dir / (i ? "ceres" : "eigen_lm");
    r = test::run_cli("odometry " + sim.string() + " --solver " + out.filename().string() +
                      " --out " + out.string());
    if (i == 1 && r.exit_code != 0 && r.output.find("without Ceres") != std::string::npos)
      GTEST_SKIP() << "built without Ceres (libceres-dev): " << r.output;
    ASSERT_EQ(r.exit_code, 0) << r.output;
    std::ifstream summary(out / "summary.json");
    EXPECT_EQ(nlohmann::json::parse(summary)["solver"].get<std::string>(), out.filename().string());
    std::ifstream in(out / "poses.txt");
    for (std::string line; std::getline(in, line);) {
      std::istringstream ss(line);
      poses[i].emplace_back(std::istream_iterator<double>(ss), std::istream_iterator<double>());
    }
  }
  ASSERT_EQ(poses[0].size(), 6u);
  ASSERT_EQ(poses[1].size(), 6u);
  for (std::size_t f = 0; f < 6; ++f)
    for (std::size_t k = 0; k < 12; ++k) EXPECT_NEAR(poses[1][f][k], poses[0][f][k], 1e-4);
}

TEST(CliOdometry, ImuAndOdomTopicsOfABagAreCheckedByType) {
  const char* bag = "legs_2d_tracking/general_tracking_moving_1.bag";
  FIELDLIDAR_REQUIRE_DATA(bag);
  const auto dir = test::temp_dir("cli_odometry_topics");
  const std::string in = test::data_file(bag).string(), out = " --out " + dir.string();
  // /odom is nav_msgs/Odometry: a wheel topic, not an IMU one.
  auto r = test::run_cli("odometry " + in + " --imu /odom" + out);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("'/odom' is nav_msgs/Odometry, not sensor_msgs/Imu"), std::string::npos)
      << r.output;
  r = test::run_cli("odometry " + in + " --odom /wheels" + out);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("no topic '/wheels'"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("/odom [nav_msgs/Odometry, 11561]"), std::string::npos) << r.output;
  // A topic name needs a bag.
  r = test::run_cli("odometry " + dir.string() + " --odom /odom" + out);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("needs a .bag INPUT"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace fieldlidar
