// End-to-end: fieldlidar navigate on a short drive of the simulated terrain (seed 0): the files,
// the summary's outcome and figures, and no output replaced without --force.

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "run_cli.hpp"
#include "test_data.hpp"

namespace fieldlidar::test {
namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), {}};
}

TEST(CliNavigate, ShortDriveWritesItsFilesAndKeepsThem) {
  const auto dir = temp_dir("cli_navigate");
  const auto out = dir / "nav";
  const std::string args =
      "navigate --scene terrain --seed 0 --start 3,20,0 --goal 9,20,0 --out " + quoted(out);
  const auto r = run_cli(args);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* n : {"plans.csv", "plans.geojson", "path.csv", "navigate_log.csv",
                        "summary.json", "navigate.png", "built_map.yaml", "built_map.pgm"})
    EXPECT_TRUE(fs::exists(out / n)) << n;
  // The map the robot built, planned on again by `fieldlidar plan`: the drive it made is clear.
  const auto replan = run_cli("plan --map " + quoted(out) + " --start 3,20,0 --goal 9,20,0 --out " +
                              quoted(dir / "replan"));
  ASSERT_EQ(replan.exit_code, 0) << replan.output;
  const auto p = nlohmann::json::parse(slurp(dir / "replan" / "summary.json"));
  EXPECT_EQ(p["status"], "success");
  EXPECT_NEAR(p["length_m"].get<double>(), 6.0, 0.5);
  const auto j = nlohmann::json::parse(slurp(out / "summary.json"));
  EXPECT_EQ(j["outcome"], "arrived");
  EXPECT_EQ(j["frames_on_impassable"], 0);
  EXPECT_LE(j["length_ratio"].get<double>(), 1.15);
  EXPECT_EQ(j["truth_plan_status"], "success");
  EXPECT_EQ(j["blind_drop_clear_m"], 1.0);  // the settings the drive ran with
  EXPECT_EQ(j["approach_m"], 2.0);
  EXPECT_EQ(j["guess_looks_allowed"], 2);
  EXPECT_EQ(j["guess_looks"], 0);
  const auto& m = j["built_map_vs_truth"];  // the map it planned on, near the drive
  EXPECT_EQ(m["radius_m"], 3.0);
  EXPECT_GT(m["known_cells"].get<int>(), 100);
  EXPECT_LE(m["truth_passable"].get<int>(), m["known_cells"].get<int>());
  EXPECT_LE(m["passable_blocked_beside_impassable"].get<int>(), m["passable_blocked"].get<int>());
  const std::string log = slurp(out / "navigate_log.csv");
  EXPECT_EQ(log.rfind("t_s,x_m,y_m,yaw_rad,", 0), 0u);
  EXPECT_NE(log.find(",impassable_depth_m,obstacle_gap_m,tilt_deg,state,"), std::string::npos);
  EXPECT_NE(log.find(",arrived,"), std::string::npos);
  const auto g = nlohmann::json::parse(slurp(out / "plans.geojson"));
  EXPECT_EQ(g["type"], "FeatureCollection");

  const auto again = run_cli(args);
  EXPECT_EQ(again.exit_code, 1);
  EXPECT_NE(again.output.find("--force"), std::string::npos) << again.output;
  EXPECT_EQ(run_cli(args + " --force").exit_code, 0);

  const auto help = run_cli("navigate --help");
  EXPECT_NE(help.output.find("(m, m, rad"), std::string::npos) << help.output;

  // Finer cells: the same drive on a 0.25 m map, scored on a 0.25 m truth; absurd cells refused.
  const auto fine = run_cli(args + " --force --cell 0.25");
  ASSERT_EQ(fine.exit_code, 0) << fine.output;
  const auto jf = nlohmann::json::parse(slurp(out / "summary.json"));
  EXPECT_EQ(jf["cell_m"], 0.25);
  EXPECT_EQ(j["cell_m"], 0.5);
  EXPECT_EQ(jf["outcome"], "arrived");
  EXPECT_EQ(jf["frames_on_impassable"], 0);
  EXPECT_LE(jf["length_ratio"].get<double>(), 1.15);
  const auto absurd = run_cli(args + " --force --cell 0.01");
  EXPECT_EQ(absurd.exit_code, 1);
  EXPECT_NE(absurd.output.find("--cell"), std::string::npos) << absurd.output;

  // The LiDAR lower on the robot: its blind disk shrinks with the height (VLP-16, 15 deg).
  EXPECT_EQ(j["mast_m"], 1.2);
  EXPECT_NEAR(j["blind_radius_m"].get<double>(), 1.2 / std::tan(15.0 * M_PI / 180.0), 0.05);
  const auto low = run_cli(args + " --force --mast 0.8");
  ASSERT_EQ(low.exit_code, 0) << low.output;
  const auto jl = nlohmann::json::parse(slurp(out / "summary.json"));
  EXPECT_EQ(jl["mast_m"], 0.8);
  EXPECT_NEAR(jl["blind_radius_m"].get<double>(), 0.8 / std::tan(15.0 * M_PI / 180.0), 0.05);
  EXPECT_EQ(jl["outcome"], "arrived");
  EXPECT_EQ(jl["frames_on_impassable"], 0);
  const auto tall = run_cli(args + " --force --mast 10");
  EXPECT_EQ(tall.exit_code, 1);
  EXPECT_NE(tall.output.find("--mast"), std::string::npos) << tall.output;
}

// --pose-source odometry: the robot maps and drives by its LiDAR odometry; the summary says so
// and gives its largest pose error against the truth. A bad name is an error naming the option.
TEST(CliNavigate, OdometryPoseSource) {
  const auto dir = temp_dir("cli_navigate_odometry");
  const auto out = dir / "nav";
  const auto r = run_cli(
      "navigate --seed 0 --start 3,20,0 --goal 9,20,0 --pose-source odometry --out " + quoted(out));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto j = nlohmann::json::parse(slurp(out / "summary.json"));
  EXPECT_EQ(j["outcome"], "arrived");
  EXPECT_EQ(j["pose_source"].get<std::string>().rfind("odometry", 0), 0u);
  EXPECT_GT(j["max_pose_error_m"].get<double>(), 0.0);
  EXPECT_LT(j["max_pose_error_m"].get<double>(), 0.3);
  const auto bad = run_cli("navigate --seed 0 --pose-source gps --out " + quoted(dir / "bad"));
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.output.find("--pose-source"), std::string::npos) << bad.output;
}

// --sensor: another multi-beam LiDAR drives the same short way (the HDL-32E's lowest beam, -30.7
// deg, meets the ground 2.0 m from the 1.2 m mast); the summary names it and its blind radius. A
// planar laser, which sees no ground, and an unknown name are errors naming the problem, before
// anything is written.
TEST(CliNavigate, SensorPreset) {
  const auto dir = temp_dir("cli_navigate_sensor");
  const auto r = run_cli("navigate --seed 0 --start 3,20,0 --goal 9,20,0 --sensor hdl32e --out " +
                         quoted(dir / "nav"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto j = nlohmann::json::parse(slurp(dir / "nav" / "summary.json"));
  EXPECT_EQ(j["outcome"], "arrived");
  EXPECT_EQ(j["frames_on_impassable"], 0);
  EXPECT_EQ(j["sensor"], "hdl32e");
  EXPECT_NEAR(j["blind_radius_m"].get<double>(), 2.02, 0.01);
  const auto planar = run_cli("navigate --seed 0 --sensor laser2d --out " + quoted(dir / "bad"));
  EXPECT_EQ(planar.exit_code, 1);
  EXPECT_NE(planar.output.find("--sensor: 'laser2d' is not a multi-beam preset"), std::string::npos)
      << planar.output;
  const auto unknown = run_cli("navigate --seed 0 --sensor hdl99 --out " + quoted(dir / "bad"));
  EXPECT_EQ(unknown.exit_code, 1);
  EXPECT_NE(unknown.output.find("--sensor"), std::string::npos) << unknown.output;
  EXPECT_FALSE(fs::exists(dir / "bad"));
}

// Two pairs, a short drive and a goal on a rock (on_a_rock of the seed-0 pairs): each in its own
// folder, the table in pairs.csv and the whole in one line.
TEST(CliNavigate, PairsAreTallied) {
  const auto dir = temp_dir("cli_navigate_pairs");
  const auto file = dir / "pairs.csv";
  std::ofstream(file) << "# name, start, goal, expect\n"
                      << "short, 3, 20, 0, 9, 20, 0, arrived\n"
                      << "on_a_rock, 3, 20, 0, 16.5, 3, 0, unreachable\n";
  const auto r =
      run_cli("navigate --seed 0 --pairs " + quoted(file) + " --out " + quoted(dir / "nav"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(dir / "nav" / "short" / "summary.json"));
  EXPECT_TRUE(fs::exists(dir / "nav" / "on_a_rock" / "summary.json"));
  EXPECT_NE(slurp(dir / "nav" / "pairs.csv").find("on_a_rock,unreachable,unreachable"),
            std::string::npos);
  EXPECT_NE(slurp(dir / "nav" / "pairs.csv")
                .find(",max_impassable_depth_m,frames_on_obstacles,min_obstacle_gap_m,"),
            std::string::npos);
  EXPECT_NE(r.output.find("2 pairs: 1 of 1 goals the truth plan reaches arrived (1 within 1.15"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("0 drives with the footprint on truth-impassable cells (0 frames; 0 "
                          "reaching 0.10 m or more into such a cell; 0 meeting an obstacle "
                          "itself); 1 of 1 goals it cannot reach reported unreachable"),
            std::string::npos)
      << r.output;
}

}  // namespace
}  // namespace fieldlidar::test
