// fieldlidar follow --replay: the follow pipeline on real 2D laser recordings (robot motion from
// the recorded odometry, or standing still); figures measured on the shared bags.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "csv_text.hpp"
#include "run_cli.hpp"
#include "test_data.hpp"

namespace fieldlidar {
namespace {

nlohmann::json summary_of(const std::filesystem::path& dir) {
  std::ifstream in(dir / "summary.json");
  std::stringstream ss;
  ss << in.rdbuf();
  return nlohmann::json::parse(ss.str());
}

std::size_t lines_of(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::size_t n = 0;
  for (std::string line; std::getline(in, line);) ++n;
  return n;
}

/// `simulate SIMULATE_ARGS` into DIR/sim, then `follow --replay` of that folder with its own
/// sensor poses (poses_tum.txt) into DIR/out; false, the failure reported, when either fails.
bool simulate_and_replay(const std::filesystem::path& dir, const std::string& simulate_args) {
  const auto sim = dir / "sim";
  auto r = test::run_cli("simulate " + simulate_args + " --out " + sim.string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  if (r.exit_code != 0) return false;
  r = test::run_cli("follow --replay " + sim.string() + " --odom " +
                    (sim / "poses_tum.txt").string() + " --out " + (dir / "out").string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return r.exit_code == 0;
}

TEST(CliFollowReplay, MovingRobotBagWithItsOdometry) {
  const char* bag = "legs_2d_tracking/general_tracking_moving_1.bag";
  FIELDLIDAR_REQUIRE_DATA(bag);
  const auto dir = test::temp_dir("cli_follow_replay");
  const auto r = test::run_cli("follow --replay " + test::data_file(bag).string() +
                               " --topic /scan --odom /odom --out " + dir.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(lines_of(dir / "follow_log.csv"), 874u);  // header + one row per scan
  const auto s = summary_of(dir);
  EXPECT_EQ(s["frames"].get<int>(), 873);
  EXPECT_EQ(s["topic"], "/scan");
  const auto& m = s["metrics"];
  // The robot's recorded path (odometry) and the commands only logged.
  EXPECT_NEAR(m["path_length_m"].get<double>(), 109.66, 0.05);
  // The laser's mount on the base, from the bag's /tf.
  EXPECT_NEAR(s["sensor_mount"]["x_m"].get<double>(), 0.850, 0.001);
  EXPECT_NEAR(s["sensor_mount"]["yaw_deg"].get<double>(), 42.1, 0.1);
  // Measured: a target (id 1) chosen after 138 scans and held in 9 of the 735 scans since (the
  // leg pipeline reports persons only once they walked 1 m; no one person is followed on this
  // multi-person bag, and a lost target is not replaced).
  const auto frames = s["frames"].get<std::size_t>();
  const auto& stopped = m["frames_stopped"];
  EXPECT_EQ(m["frames_following"].get<std::size_t>() +
                stopped["idle_no_target"].get<std::size_t>() +
                stopped["too_close"].get<std::size_t>() + stopped["too_far"].get<std::size_t>() +
                stopped["lost"].get<std::size_t>(),
            frames);
  EXPECT_GE(m["target_held_fraction"].get<double>(), 0.012);
  EXPECT_GE(m["frames_following"].get<int>(), 9);
  EXPECT_LE(m["target_switches"].get<int>(), 1);
  EXPECT_GT(m["mean_perception_ms"].get<double>(), 0.0);  // timed by the benchmarks, not here
  // The picture: a PNG of the path, the target estimates and the states' timeline.
  const auto png = dir / "follow.png";
  ASSERT_TRUE(std::filesystem::exists(png));
  std::ifstream png_in(png, std::ios::binary);
  char signature[8] = {};
  png_in.read(signature, 8);
  EXPECT_EQ(std::string(signature + 1, 3), "PNG");
  const auto png_bytes = std::filesystem::file_size(png);
  EXPECT_GT(png_bytes, 20000u);
  // Never overwrites without --force: a picture left alone blocks the run as well.
  std::filesystem::remove(dir / "follow_log.csv");
  std::filesystem::remove(dir / "summary.json");
  const auto again = test::run_cli("follow --replay " + test::data_file(bag).string() +
                                   " --odom /odom --out " + dir.string());
  EXPECT_NE(again.exit_code, 0);
  EXPECT_NE(again.output.find("follow.png"), std::string::npos) << again.output;
  EXPECT_EQ(std::filesystem::file_size(png), png_bytes);
  EXPECT_FALSE(std::filesystem::exists(dir / "summary.json"));
  const auto wrong = test::run_cli("follow --replay " + test::data_file(bag).string() +
                                   " --odom /scan --out " + dir.string() + "/x");
  EXPECT_NE(wrong.exit_code, 0);
  EXPECT_NE(wrong.output.find("not nav_msgs/Odometry or geometry_msgs/TwistStamped"),
            std::string::npos)
      << wrong.output;
}

TEST(CliFollowReplay, StandingRobotWithPeopleAndWithNone) {
  const char* positive = "legs_2d/positive_3_extracted.bag";
  const char* negative = "legs_2d/negative_2.bag";
  FIELDLIDAR_REQUIRE_DATA(positive);
  FIELDLIDAR_REQUIRE_DATA(negative);
  const auto dir = test::temp_dir("cli_follow_replay_still");
  auto r = test::run_cli("follow --replay " + test::data_file(positive).string() + " --out " +
                         (dir / "pos").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // Its output is no terminal: no progress line of carriage returns (support/progress_line.hpp).
  EXPECT_EQ(r.output.find('\r'), std::string::npos);
  auto s = summary_of(dir / "pos");
  EXPECT_EQ(s["motion"], "standing still");
  // Measured (joint person tracker, ego-motion by scan matching): target chosen after 15 of 175
  // scans, held in 75.0 % of the scans since, 99 scans following (positive_1/2/4: 72.0 / 69.2 /
  // 49.3 %). Before reported persons were also updated by carried legs (leg-sized segments the
  // classifier did not take, near them) and only persons seen in the scan were driven on: 58.8 %,
  // 76 scans following (positive_1/2/4 alike).
  EXPECT_GE(s["metrics"]["target_held_fraction"].get<double>(), 0.70);
  EXPECT_GE(s["metrics"]["frames_following"].get<int>(), 90);
  // The extracted bag has 2 breaks (over 1 s between scans): the operator, lost across each,
  // is taken back after 12 scans; without those 24 scans held in 87.7 % (89.0 % before walking
  // legs were kept out of the fast grids; the other lost scans end the bag).
  EXPECT_EQ(s["metrics"]["recording_gaps"].get<int>(), 2);
  EXPECT_LE(s["metrics"]["frames_lost_after_gaps"].get<int>(), 30);
  EXPECT_GE(s["metrics"]["target_held_fraction_between_gaps"].get<double>(), 0.85);
  // positive_4: the operator's person track of the leg pipeline coasts over a few scans without
  // legs and the follow tracker's own track of them dies; the pipeline's track reported again is
  // the target again at once (Perception::people_ids): held in 75.2 % of the scans since chosen
  // (49.3 % before: lost for 147 scans until they walked 1 m). Standing 0.5 m from the sensor,
  // a cell from the robot's own returns, their legs are then taken into the background grids;
  // sure legs near a reported person still count (LegPipeline2DConfig::sure_leg_radius_m):
  // measured 95.2 %.
  const char* positive_4 = "legs_2d/positive_4_extracted.bag";
  FIELDLIDAR_REQUIRE_DATA(positive_4);
  r = test::run_cli("follow --replay " + test::data_file(positive_4).string() + " --out " +
                    (dir / "pos4").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto pos4 = summary_of(dir / "pos4")["metrics"];
  EXPECT_GE(pos4["target_held_fraction"].get<double>(), 0.90);
  // Its one break (14 scans lost after it) is the rest: held in every other scan (measured 1.0).
  EXPECT_EQ(pos4["recording_gaps"].get<int>(), 1);
  EXPECT_GE(pos4["target_held_fraction_between_gaps"].get<double>(), 0.99);
  // No person in the scene: every scan the mower follows is a false follow. Measured: 0 of 434
  // scans on /right_scan since standing pairs need a person's shape (11 before: two blobs 0.2-0.35
  // m wide, 0.5 m apart, taken for a standing person); 0 on /left_scan and /rear_scan.
  r = test::run_cli("follow --replay " + test::data_file(negative).string() +
                    " --topic /right_scan --out " + (dir / "neg").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  s = summary_of(dir / "neg");
  EXPECT_LE(s["metrics"]["frames_following"].get<int>(), 3);
}

// The 2D path on simulated 2D laser scans (`simulate --sensor laser2d`): the scene's scripted
// mower drives 2.5 m behind the operator from the first scan. Measured: target chosen after 17
// of 300 scans, held in all since (scene seeds 1-5: 12-29 scans). Walking along with the moving
// robot, the operator keeps their place in the sensor frame; before the follow zone was kept out
// of the fast sensor-frame occupancy grid (LegPipeline2DConfig::zone_turn_rate_max_deg_s) that
// grid took their legs before a track was reported: chosen after 221 scans (docs/people.md).
TEST(CliFollowReplay, SimulatedLawnTwoDimensionalScans) {
  const auto dir = test::temp_dir("cli_follow_replay_sim_2d");
  ASSERT_TRUE(simulate_and_replay(dir, "--scene lawn --sensor laser2d --frames 300"));
  const auto s = summary_of(dir / "out");
  EXPECT_EQ(s["frames"].get<int>(), 300);
  const auto& m = s["metrics"];
  EXPECT_LE(m["frames_before_target_chosen"].get<int>(), 25);
  EXPECT_GE(m["target_held_fraction"].get<double>(), 0.98);
  EXPECT_EQ(m["target_switches"].get<int>(), 0);
}

TEST(CliFollowReplay, SimulatedLawnSweepsWithTheirPoses) {
  // The 3D path: simulated VLP-16 sweeps of the lawn (the operator walks ahead of the moving
  // sensor), the sensor's poses from the folder's poses_tum.txt.
  const auto dir = test::temp_dir("cli_follow_replay_sim");
  ASSERT_TRUE(simulate_and_replay(dir, "--scene lawn --frames 60"));
  const auto s = summary_of(dir / "out");
  EXPECT_EQ(s["frames"].get<int>(), 60);
  const auto& m = s["metrics"];
  // Measured (150 frames): target chosen after 2 sweeps, held in all since, 148 following.
  EXPECT_LE(m["frames_before_target_chosen"].get<int>(), 3);
  EXPECT_GE(m["target_held_fraction"].get<double>(), 0.98);
  EXPECT_GE(m["frames_following"].get<int>(), 55);
  EXPECT_EQ(m["target_switches"].get<int>(), 0);
  EXPECT_GT(m["path_length_m"].get<double>(), 3.0);
}

// The 2D path on a simulated lawn with three people strolling at random and one crossing ahead
// of the operator (scene seed 1: a stroller passes 0.5 m from the operator at scan 272), the
// scripted mower 2.5 m behind the operator: the target is the operator in every scan it is held.
// Measured: chosen after 12 scans, held in all 388 since, each within 0.5 m of the operator
// (scene seeds 0-5 over 2000 scans: 0, 1, 3, 4, 5 likewise; on seed 2 a stroller walks through
// the operator, in the simulator literally, and is taken for them: 140 scans off, then lost).
TEST(CliFollowReplay, SimulatedLawnWithStrollersTheTargetStaysTheOperator) {
  const auto dir = test::temp_dir("cli_follow_replay_sim_2d_strollers");
  const auto sim = dir / "sim", out = dir / "out";
  ASSERT_TRUE(simulate_and_replay(
      dir, "--scene lawn --sensor laser2d --frames 400 --seed 1 --extra-walkers 3 --crossing"));
  std::map<int, Eigen::Vector2d> operator_at;  // people.csv: frame, stamp, id, x, y, ...
  for (const auto& f : test::csv_text_rows(sim / "people.csv"))
    if (f.size() > 4 && f[2] == "1")
      operator_at[std::stoi(f[0])] = {std::stod(f[3]), std::stod(f[4])};
  const auto log =
      test::csv_text_rows(out / "follow_log.csv");  // t, mower x y yaw, est_x, est_y, ...
  ASSERT_EQ(log.size(), 400u);
  int held = 0, off = 0;
  for (std::size_t i = 0; i < log.size(); ++i) {
    if (log[i].size() < 6 || log[i][4] == "nan") continue;
    ++held;
    const Eigen::Vector2d est(std::stod(log[i][4]), std::stod(log[i][5]));
    ASSERT_TRUE(operator_at.count(int(i)));
    off += (est - operator_at[int(i)]).norm() > 0.5;
  }
  EXPECT_GE(held, 380);
  EXPECT_EQ(off, 0);
}

}  // namespace
}  // namespace fieldlidar
