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

// NaN or inf in the motion streams or the options would be integrated into every later pose:
// refused before any output is written, naming the file, line and column or the option.
TEST(CliOdometry, NonFiniteImuWheelsAndOptionsAreRefused) {
  const auto dir = test::temp_dir("cli_odometry_nonfinite");
  const auto sim = dir / "sim";
  auto r = test::run_cli("simulate --scene greenhouse --frames 2 --out " + test::quoted(sim));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string imu_header =
      "stamp_s,gyro_x_rad_s,gyro_y_rad_s,gyro_z_rad_s,accel_x_m_s2,accel_y_m_s2,accel_z_m_s2\n";
  std::ofstream(dir / "imu_nan.csv") << imu_header << "0,0,0,0,0,0,9.8\n0.01,nan,0,0,0,0,9.8\n";
  std::ofstream(dir / "wheel_nan.csv") << "stamp,linear,yaw_rate\n0,nan,0\n";
  std::ofstream(dir / "odom_inf.csv")
      << "stamp_s,left_m_s,right_m_s,left_rad_s,right_rad_s,linear_m_s,yaw_rate_rad_s,dr_x_m,"
         "dr_y_m,dr_yaw_rad\n0,0,0,0,0,0,0,0,0,0\n0.02,0,0,0,0,0,0,0,0,inf\n";
  const std::string in = test::quoted(sim);
  const struct {
    std::string args, message;
  } cases[] = {
      {"--imu " + test::quoted(dir / "imu_nan.csv"),
       "imu_nan.csv: line 3: gyro_x_rad_s is nan, not a finite number"},
      {"--odom " + test::quoted(dir / "wheel_nan.csv"),
       "wheel_nan.csv: line 2: linear is nan, not a finite number"},
      {"--odom " + test::quoted(dir / "odom_inf.csv"),
       "odom_inf.csv: line 3: dr_yaw_rad is inf, not a finite number"},
      {"--initial-pose nan 0 0 0 0 0", "--initial-pose: must be a finite number, got 'nan'"},
      {"--elevation-correction nan", "--elevation-correction: must be a number in [-2, 2]"},
  };
  for (const auto& c : cases) {
    const auto out = dir / "out";
    r = test::run_cli("odometry " + in + " " + c.args + " -o " + test::quoted(out));
    EXPECT_EQ(r.exit_code, 1) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find("fieldlidar: error: "), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(c.message), std::string::npos) << c.args << "\n" << r.output;
    EXPECT_FALSE(std::filesystem::exists(out)) << c.args;  // no empty folder left either
  }
}

// Localisation with nothing to localise in: a map without points, or one no frame matches.
TEST(CliOdometry, EmptyMapAndAMapNoFrameRegistersInAreErrors) {
  const auto dir = test::temp_dir("cli_odometry_map_in");
  const auto sim = dir / "sim";
  auto r = test::run_cli("simulate --scene greenhouse --frames 2 --out " + test::quoted(sim));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string header =
      "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH {N}\nHEIGHT "
      "1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS {N}\nDATA ascii\n";
  auto pcd_header = [&](int n) {
    std::string h = header;
    for (std::size_t at; (at = h.find("{N}")) != std::string::npos;)
      h.replace(at, 3, std::to_string(n));
    return h;
  };
  std::ofstream(dir / "empty.pcd") << pcd_header(0);
  {
    // A wall of planes 5 km away: nothing of the greenhouse falls near it.
    std::ofstream far(dir / "far.pcd");
    far << pcd_header(400);
    for (int i = 0; i < 20; ++i)
      for (int j = 0; j < 20; ++j) far << 5000 << ' ' << 0.2 * i << ' ' << 0.2 * j << '\n';
  }
  r = test::run_cli("odometry " + test::quoted(sim) + " --map-in " +
                    test::quoted(dir / "empty.pcd") + " -o " + test::quoted(dir / "o1"));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("empty.pcd: the map has no points"), std::string::npos) << r.output;
  r = test::run_cli("odometry " + test::quoted(sim) + " --map-in " + test::quoted(dir / "far.pcd") +
                    " -o " + test::quoted(dir / "o2"));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("none of the 2 frames registered in the map"), std::string::npos)
      << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "o2" / "poses.txt"));
}

}  // namespace
}  // namespace fieldlidar
