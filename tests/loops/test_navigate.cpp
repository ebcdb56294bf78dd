// The navigate loop (seed 004 closed loop) on short drives of the simulated terrain scene of seed
// 0: the robot maps, plans, follows and arrives, its footprint never on a truth-impassable cell,
// its driven length within 1.15 x the Hybrid A* path planned on the truth map.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <string>
#include <tuple>

#include <gtest/gtest.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/loops/navigate.hpp"
#include "fieldlidar/loops/navigate_maps.hpp"
#include "fieldlidar/loops/navigate_pairs.hpp"
#include "fieldlidar/sim/scenes.hpp"
#include "fieldlidar/terrain/traversability.hpp"
#include "test_data.hpp"

using namespace fieldlidar;
using fieldlidar::planning::Pose2;

namespace {

const sim::Scene& scene0() {
  static const sim::Scene scene = sim::make_terrain_scene({}, 0);
  return scene;
}

void print(const char* name, const loops::NavigateResult& r) {
  std::printf(
      "%s: %s (%s), driven %.2f m, truth plan %.2f m, ratio %.3f, %d replans, %zu frames "
      "on impassable, %zu scans, %.1f s simulated, %.1f s wall\n",
      name, loops::to_string(r.outcome), r.reason.c_str(), r.driven_length_m, r.truth_length_m,
      r.length_ratio, r.replans, r.frames_on_impassable, r.scans, r.duration_s, r.wall_s);
}

}  // namespace

// Along the open middle of the scene, 13 m. Measured: see the test's output.
TEST(Navigate, ShortDriveArrives) {
  const auto r = loops::run_navigate(scene0(), SensorModel::vlp16(), {3, 20, 0}, {16, 20, 0});
  print("along_route", r);
  EXPECT_EQ(r.outcome, loops::NavigateOutcome::kArrived) << r.reason;
  EXPECT_EQ(r.frames_on_impassable, 0u);
  ASSERT_TRUE(std::isfinite(r.length_ratio));
  EXPECT_LE(r.length_ratio, 1.15);
  EXPECT_GT(r.length_ratio, 0.9);
  EXPECT_FALSE(r.rows.empty());
  EXPECT_EQ(r.rows.back().state, loops::NavigateState::kArrived);
}

// Facing the scene's west edge 1.2 m away: the way out needs a reverse run.
TEST(Navigate, BacksOutFromTheEdge) {
  const auto r =
      loops::run_navigate(scene0(), SensorModel::vlp16(), {1.2, 20, std::numbers::pi}, {8, 20, 0});
  print("reverse_out", r);
  EXPECT_EQ(r.outcome, loops::NavigateOutcome::kArrived) << r.reason;
  EXPECT_EQ(r.frames_on_impassable, 0u);
  EXPECT_LE(r.length_ratio, 1.15);
  bool reversed = false;
  for (const auto& row : r.rows) reversed |= row.v_m_s < -0.05;
  EXPECT_TRUE(reversed);
}

TEST(Navigate, BadInputIsAnError) {
  EXPECT_THROW(loops::run_navigate(scene0(), SensorModel::vlp16(), {NAN, 20, 0}, {8, 20, 0}),
               Error);
  EXPECT_THROW(loops::run_navigate(scene0(), SensorModel::vlp16(), {3, 20, 0}, {80, 20, 0}), Error);
  // A planar laser sees no ground to map.
  EXPECT_THROW(loops::run_navigate(scene0(), SensorModel::laser_2d(), {3, 20, 0}, {8, 20, 0}),
               Error);
  // A nodding 2D laser has planes below the horizon, but it is no spinning LiDAR.
  EXPECT_THROW(loops::check_navigate_sensor(SensorModel::tilting_2d()), Error);
  EXPECT_NO_THROW(loops::check_navigate_sensor(SensorModel::os1_64()));
  // Each setting alone, on the defaults otherwise.
  const auto rejected = [](const char* what, auto set) {
    loops::NavigateConfig bad;
    set(bad);
    EXPECT_THROW(loops::run_navigate(scene0(), SensorModel::vlp16(), {3, 20, 0}, {8, 20, 0}, bad),
                 Error)
        << what;
  };
  rejected("fusion.layers.robot.min_turn_radius_m",
           [](loops::NavigateConfig& c) { c.fusion.layers.robot.min_turn_radius_m = 0.0; });
  rejected("lidar_pitch_deg", [](loops::NavigateConfig& c) { c.lidar_pitch_deg = 40.0; });
  rejected("start_look_rad", [](loops::NavigateConfig& c) { c.start_look_rad = NAN; });
  rejected("approach_m", [](loops::NavigateConfig& c) { c.approach_m = -1.0; });
  rejected("escape_max_m", [](loops::NavigateConfig& c) { c.escape_max_m = NAN; });
  rejected("start_disk_tau", [](loops::NavigateConfig& c) { c.start_disk_tau = 2.0; });
  rejected("blocked_goal_look_m",
           [](loops::NavigateConfig& c) { c.blocked_goal_look_m = INFINITY; });
  rejected("blocked_goal_approach_m",
           [](loops::NavigateConfig& c) { c.blocked_goal_approach_m = -1.0; });
  rejected("blind_drop_clear_m", [](loops::NavigateConfig& c) { c.blind_drop_clear_m = NAN; });
  rejected("blind_drop_clear_m", [](loops::NavigateConfig& c) { c.blind_drop_clear_m = -1.0; });
  rejected("tilt_stop_deg", [](loops::NavigateConfig& c) { c.tilt_stop_deg = NAN; });
  rejected("tilt_stop_deg", [](loops::NavigateConfig& c) { c.tilt_stop_deg = 95.0; });
  rejected("guess_looks", [](loops::NavigateConfig& c) { c.guess_looks = -1; });
  rejected("guess_look_margin_m", [](loops::NavigateConfig& c) { c.guess_look_margin_m = NAN; });
  rejected("replan_switch_gain", [](loops::NavigateConfig& c) { c.replan_switch_gain = 1.0; });
  rejected("replan_switch_gain", [](loops::NavigateConfig& c) { c.replan_switch_gain = NAN; });
}

// A goal whose footprint a blocked cell (an obstacle's halo) touches is moved to the nearest free
// pose within the tolerance, same heading; a goal inside a wide obstacle has none.
TEST(Navigate, BlockedGoalMovesToTheNearestFreePose) {
  Grid2D grid(GridGeometry{.resolution_m = 0.5, .origin_m = {0, 0}, .width = 20, .height = 20});
  auto tau = grid.add_layer(terrain::layer::kTraversability, 1.0f);
  for (int iy = 0; iy < 20; ++iy) tau[grid.geometry().linear_index(11, iy)] = 0.0f;  // x 5.5-6
  for (int iy = 0; iy < 20; ++iy)
    for (int ix = 14; ix < 20; ++ix) tau[grid.geometry().linear_index(ix, iy)] = 0.0f;
  const terrain::RobotConfig robot;
  const planning::PlanningMap map(grid, robot, {});
  // Heading north, 0.29 m + 0.05 m margin each side: x = 5.1 reaches 5.44 plus the masks' cell
  // rounding; a few tenths west it is free.
  const Pose2 goal{5.1, 5.0, std::numbers::pi / 2};
  ASSERT_FALSE(map.pose_free(goal));
  const auto moved = loops::nearest_free_pose(map, goal, 0.3);
  ASSERT_TRUE(moved.has_value());
  EXPECT_TRUE(map.pose_free(*moved));
  EXPECT_LE(std::hypot(moved->x_m - goal.x_m, moved->y_m - goal.y_m), 0.3 + 1e-9);
  EXPECT_LT(moved->x_m, goal.x_m);
  EXPECT_EQ(moved->yaw_rad, goal.yaw_rad);
  EXPECT_FALSE(loops::nearest_free_pose(map, {8.5, 5.0, 0.0}, 0.3).has_value());
  EXPECT_EQ(loops::nearest_free_pose(map, {2.0, 5.0, 0.0}, 0.3)->x_m, 2.0);  // already free
}

// The cold-start creep: the first plan is a straight run along the start heading, one blind
// radius long (1.2 m / tan 15 deg = 4.48 m for the VLP-16), driven at no more than the creep
// speed; then the robot plans to the goal and arrives.
TEST(Navigate, StartCreepGoesStraightFirst) {
  loops::NavigateConfig cfg;
  cfg.start_creep_m = -1.0;
  const auto r = loops::run_navigate(scene0(), SensorModel::vlp16(), {3, 20, 0}, {16, 20, 0}, cfg);
  print("along_route, creep", r);
  EXPECT_EQ(r.outcome, loops::NavigateOutcome::kArrived) << r.reason;
  ASSERT_GE(r.plans.size(), 2u);
  EXPECT_EQ(r.plans[0].trigger, "start_creep");
  EXPECT_NEAR(r.plans[0].length_m, 1.2 / std::tan(15.0 * std::numbers::pi / 180), 0.05);
  for (const auto& p : r.plans[0].path) EXPECT_NEAR(p.pose.y_m, 20.0, 1e-9);
  EXPECT_EQ(r.plans[1].trigger, "creep_done");
  for (const auto& row : r.rows)
    if (row.t_s < r.plans[1].t_s) {
      EXPECT_LE(std::abs(row.v_m_s), cfg.creep_speed_m_s + 1e-9);
    }
  EXPECT_EQ(r.frames_on_impassable, 0u);
  EXPECT_LE(r.length_ratio, 1.15);
}

// The start look with a LiDAR pitched 10 deg forward: the robot turns once in place (at the look
// rate, its position unchanged) before the first plan, then plans, drives and arrives.
TEST(Navigate, StartLookTurnsInPlaceBeforeTheFirstPlan) {
  loops::NavigateConfig cfg;
  cfg.lidar_pitch_deg = 10.0;
  cfg.start_look_rad = 2.0 * std::numbers::pi;
  const auto r = loops::run_navigate(scene0(), SensorModel::vlp16(), {3, 20, 0}, {16, 20, 0}, cfg);
  print("along_route, pitched, look", r);
  EXPECT_EQ(r.outcome, loops::NavigateOutcome::kArrived) << r.reason;
  ASSERT_FALSE(r.plans.empty());
  EXPECT_EQ(r.plans[0].trigger, "start");
  EXPECT_GE(r.plans[0].t_s, cfg.start_look_rad / cfg.look_yaw_rate_rad_s - 0.15);
  double turned = 0.0;
  for (const auto& row : r.rows)
    if (row.t_s < r.plans[0].t_s) {
      EXPECT_EQ(row.x_m, 3.0);
      EXPECT_EQ(row.y_m, 20.0);
      EXPECT_EQ(row.v_m_s, 0.0);
      turned += row.yaw_rate_rad_s * cfg.control_period_s;
    }
  EXPECT_NEAR(turned, cfg.start_look_rad, cfg.look_yaw_rate_rad_s * cfg.control_period_s + 1e-9);
  EXPECT_EQ(r.frames_on_impassable, 0u);
  EXPECT_LE(r.length_ratio, 1.15);
}

// Seed 0 round_hill (44 s simulated, about 2 s each in Release): the passage east of the hill is
// blocked for a while at 5 m; the detour hold keeps to the plan and passes once it clears (ratio
// 1.029 measured); without it the robot turns back towards the 60 m detour round the hill's
// west and north before the passage reopens (1.342). A cold start (approach_m 0): with the
// default 2 m approach the block is not seen from afar and both drives measure 1.059. The block
// was the hill's lower flank, whose first ground the sparse sensor sees above the plane round
// the robot; the ground segmentation now takes it as ground (RobustGroundConfig::
// first_cell_max_rise_m: both drives 1.034), so the test turns that rule off to keep a
// block seen from afar that later clears; the drop bands (NavigateConfig::drop_band_max_m) too:
// with them, both drives measure 1.034 again; and the lone ring's level plane
// (TraversabilityConfig::min_plane_spread_m), with which the flank reads passable from afar as
// well (both drives 1.060), and the levelling the navigate loop turns off
// (navigate_fusion_config: both drives 1.038 without it); and every periodic plan is taken
// (NavigateConfig::replan_switch_gain: without the hold 1.034 when they are put off).
TEST(Navigate, DetourHoldWaitsForABlockSeenFromAfar) {
  const sim::Scene scene = sim::make_terrain_scene({}, 0);
  const planning::Pose2 start{31, 32, 0}, goal{57, 32, 1.5708};
  loops::NavigateConfig cfg;
  cfg.approach_m = 0.0;
  cfg.fusion.layers.ground.robust.first_cell_max_rise_m = 0.0;
  cfg.drop_band_max_m = 0.0;
  cfg.fusion.layers.min_plane_spread_m = 0.0;
  cfg.fusion.layers.ground.levelling.enabled = true;
  cfg.replan_switch_gain = 0.0;
  const auto held = loops::run_navigate(scene, SensorModel::vlp16(), start, goal, cfg);
  cfg.detour_hold_ratio = 0.0;
  const auto swapped = loops::run_navigate(scene, SensorModel::vlp16(), start, goal, cfg);
  std::printf("with the hold: %s, ratio %.3f; without: %s, ratio %.3f (%s)\n",
              loops::to_string(held.outcome), held.length_ratio, loops::to_string(swapped.outcome),
              swapped.length_ratio, swapped.reason.c_str());
  EXPECT_EQ(held.outcome, loops::NavigateOutcome::kArrived) << held.reason;
  EXPECT_EQ(held.frames_on_impassable, 0u);
  EXPECT_LE(held.length_ratio, 1.10);
  EXPECT_GT(swapped.length_ratio, 1.25);
}

// A goal 21 m away on flat ground (seed 8, a random pair of the kind of
// navigate_pairs_terrain_seed2..5.csv) whose cells the map blocks as seen from the start, on a
// few returns: the robot drives to the free pose nearest it, looks again from there and arrives
// (ratio 1.020 measured); without that look (blocked_goal_look_m 0) it gives up after 3.3 m,
// "goal_in_collision on two successive map updates".
TEST(Navigate, GoalBlockedFromAfarIsLookedAtFromNear) {
  const sim::Scene scene = sim::make_terrain_scene({}, 8);
  const planning::Pose2 start{32.5, 18.3, 1.479}, goal{10.9, 19.6, 0.786};
  loops::NavigateConfig cfg;
  const auto looked = loops::run_navigate(scene, SensorModel::vlp16(), start, goal, cfg);
  cfg.blocked_goal_look_m = 0.0;
  const auto gave_up = loops::run_navigate(scene, SensorModel::vlp16(), start, goal, cfg);
  std::printf("looked: %s, ratio %.3f; without the look: %s after %.1f m (%s)\n",
              loops::to_string(looked.outcome), looked.length_ratio,
              loops::to_string(gave_up.outcome), gave_up.driven_length_m, gave_up.reason.c_str());
  EXPECT_EQ(looked.outcome, loops::NavigateOutcome::kArrived) << looked.reason;
  EXPECT_EQ(looked.frames_on_impassable, 0u);
  EXPECT_LE(looked.length_ratio, 1.10);
  EXPECT_EQ(gave_up.outcome, loops::NavigateOutcome::kUnreachable) << gave_up.reason;
  EXPECT_LT(gave_up.driven_length_m, 10.0);
}

// A goal on the hill's flank (seed 13 p9 of navigate_pairs_terrain_seed13.csv; 10-20 deg ground
// seen from below) whose cells hold returns the ground segmentation did not keep as ground until
// the robot is within 4 m: judged from there (blocked_goal_look_m 4, the default) it is reached
// (ratio 1.101 measured); judged from 8 m it was called unreachable after 24.8 m. With the
// sweeps segmented in the robot's own frame (navigate_fusion_config: no levelling, the default)
// the flank's returns are ground from 8 m as well and both drives arrive, so the test levels
// the sweeps to keep the case.
TEST(Navigate, GoalOnTheHillFlankIsJudgedFromNear) {
  const sim::Scene scene = sim::make_terrain_scene({}, 13);
  const planning::Pose2 start{55.2, 7.0, 1.405}, goal{53.3, 36.9, 1.004};
  loops::NavigateConfig cfg;
  cfg.fusion.layers.ground.levelling.enabled = true;
  const auto near = loops::run_navigate(scene, SensorModel::vlp16(), start, goal, cfg);
  cfg.blocked_goal_look_m = 8.0;
  const auto far = loops::run_navigate(scene, SensorModel::vlp16(), start, goal, cfg);
  std::printf("judged from 4 m: %s, ratio %.3f; from 8 m: %s after %.1f m (%s)\n",
              loops::to_string(near.outcome), near.length_ratio, loops::to_string(far.outcome),
              far.driven_length_m, far.reason.c_str());
  EXPECT_EQ(near.outcome, loops::NavigateOutcome::kArrived) << near.reason;
  EXPECT_EQ(near.frames_on_impassable, 0u);
  EXPECT_LE(near.length_ratio, 1.15);
  EXPECT_EQ(far.outcome, loops::NavigateOutcome::kUnreachable) << far.reason;
}

// A pairs file: comments and blank lines skipped, the expectation optional; a line that is not a
// pair, a bad name or a bad expectation is an error naming the file's line.
TEST(Navigate, PairsFileIsReadAndBadLinesNameTheirLine) {
  const auto dir = test::temp_dir("navigate_pairs_file");
  const auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir / name) << text;
    return (dir / name).string();
  };
  const auto pairs = loops::read_navigate_pairs(
      write("good.csv",
            "# name, start, goal, expect\n\nshort, 3, 20, 0, 9, 20, 0.5, arrived\n"
            "far,1,2,3,4,5,6  # no expectation\n"));
  ASSERT_EQ(pairs.size(), 2u);
  EXPECT_EQ(pairs[0].name, "short");
  EXPECT_EQ(pairs[0].expect, "arrived");
  EXPECT_EQ(pairs[0].goal.yaw_rad, 0.5);
  EXPECT_EQ(pairs[1].start.y_m, 2.0);
  EXPECT_EQ(pairs[1].expect, "");
  for (const auto& [name, text, says] :
       {std::tuple{"short.csv", "a, 1, 2, 3\n", "line 1"},
        std::tuple{"number.csv", "# x\na, 1, 2, 3, 4, y, 6\n", "line 2 goal"},
        std::tuple{"name.csv", "../a, 1, 2, 3, 4, 5, 6\n", "not a folder name"},
        std::tuple{"expect.csv", "a, 1, 2, 3, 4, 5, 6, maybe\n", "not arrived or unreachable"},
        std::tuple{"empty.csv", "# nothing\n", "no pair"}}) {
    try {
      loops::read_navigate_pairs(write(name, text));
      ADD_FAILURE() << name << ": no error";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(loops::read_navigate_pairs((dir / "missing.csv").string()), Error);
}
