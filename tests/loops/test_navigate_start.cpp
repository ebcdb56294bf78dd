// The navigate loop's start beside an obstacle: the approach's sweeps put a rock in the roof
// LiDAR's blind disk into the map before the first plan (NavigateConfig::approach_m), and a pose
// the planner calls in collision is left by the shortest move the step check allows
// (escape_path); a terrace's edge ahead in the blind disk is read from the lower ground beyond it
// (mark_blind_drops); a trench no rule sees ends the drive into it at the tilt stop; a lane the
// blind drops close is looked at before the goal is given up (NavigateConfig::guess_looks).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include <gtest/gtest.h>

#include "fieldlidar/core/labels.hpp"
#include "fieldlidar/loops/navigate.hpp"
#include "fieldlidar/loops/navigate_maps.hpp"
#include "fieldlidar/sim/mesh.hpp"
#include "fieldlidar/terrain/traversability.hpp"

using namespace fieldlidar;
using fieldlidar::planning::Pose2;

namespace {

/// Flat ground over [0, 30] x [0, 20] m, the seed's 1.2 m mast, and a 0.6 x 0.6 x 0.47 m rock
/// whose near side is 0.4 m beside the chassis of a robot at (10, 10) heading east: under the
/// lowest beam of a VLP-16 (-15 deg) from anywhere within 2.7 m of it.
sim::Scene rock_beside_start() {
  sim::Scene scene(sim::SceneKind::kCustom,
                   sim::HeightField({0, 0}, {30, 20}, 0.5, [](double, double) { return 0.0; }));
  scene.set_sensor_height_m(1.2);
  const Eigen::Vector2d rock(10.6, 10.99);
  scene.add_mesh(sim::make_aabb({rock.x() - 0.3, rock.y() - 0.3, 0.0},
                                {rock.x() + 0.3, rock.y() + 0.3, 0.47},
                                make_label(LabelClass::kObstacle)));
  scene.add_obstacle({rock, 0.3, 0.0, 0.47, LabelClass::kObstacle});
  return scene;
}

/// A 0.5 m high terrace over x < 12 m (the rest of [0, 30] x [0, 20] m at 0): its edge, a step
/// down the robot cannot take, 2 m ahead of a robot at (10, 10) heading east.
sim::Scene terrace_edge_ahead() {
  sim::Scene scene(sim::SceneKind::kCustom,
                   sim::HeightField({0, 0}, {30, 20}, 0.25,
                                    [](double x, double) { return x < 12.0 ? 0.5 : 0.0; }));
  scene.set_sensor_height_m(1.2);
  return scene;
}

/// A trench across the way of a robot at (10, 10) heading east: 0.6 m deep, a 1 m flat bottom
/// and 50 deg walls, its near edge `ahead_m` ahead, `half_m` either side of y = 10, on flat ground
/// over [0, 30] x [0, 20] m.
sim::Scene trench_ahead(double ahead_m, double half_m) {
  const double run = 0.6 / std::tan(50.0 * std::numbers::pi / 180), x0 = 10.0 + ahead_m;
  sim::Scene scene(sim::SceneKind::kCustom,
                   sim::HeightField({0, 0}, {30, 20}, 0.1, [=](double x, double y) {
                     if (std::abs(y - 10.0) > half_m) return 0.0;
                     const double d = std::abs(x - (x0 + run + 0.5));
                     return d < 0.5 ? -0.6 : d < 0.5 + run ? -0.6 * (0.5 + run - d) / run : 0.0;
                   }));
  scene.set_sensor_height_m(1.2);
  return scene;
}

/// A lane on flat ground over [0, 30] x [0, 20] m: a 1 m high wall (a step) over y < 8 m and a
/// ditch along x, 0.6 m deep with 50 deg walls and a 1 m flat bottom, its near lip at y = 11.9 m.
sim::Scene lane_beside_ditch() {
  const double run = 0.6 / std::tan(50.0 * std::numbers::pi / 180), axis = 11.9 + run + 0.5;
  sim::Scene scene(sim::SceneKind::kCustom,
                   sim::HeightField({0, 0}, {30, 20}, 0.1, [=](double, double y) {
                     if (y < 8.0) return 1.0;
                     const double d = std::abs(y - axis);
                     return d < 0.5 ? -0.6 : d < 0.5 + run ? -0.6 * (0.5 + run - d) / run : 0.0;
                   }));
  scene.set_sensor_height_m(1.2);
  return scene;
}

}  // namespace

// Started 2 m from a terrace's edge, facing it, with the goal below: no way down. The lip and
// the shadow below it lie in the blind disk, the approach sees the lower ground only from 4.3 m
// ahead; without the blind drops (loops::mark_blind_drops) the robot drives off the edge.
TEST(NavigateStart, BlindDropsKeepTheRobotOnATerrace) {
  const sim::Scene scene = terrace_edge_ahead();
  const Pose2 start{10, 10, 0}, goal{20, 10, 0};
  loops::NavigateConfig cfg;
  for (double clear : {0.0, cfg.blind_drop_clear_m}) {
    cfg.blind_drop_clear_m = clear;
    const auto r = loops::run_navigate(scene, SensorModel::vlp16(), start, goal, cfg);
    std::printf("blind drops from %.1f m: %s (%s), %zu frames on impassable, %.1f m driven\n",
                clear, loops::to_string(r.outcome), r.reason.c_str(), r.frames_on_impassable,
                r.driven_length_m);
    EXPECT_NE(r.truth_status, planning::PlanStatus::kSuccess);  // the truth: no way down
    if (clear == 0.0) {
      EXPECT_GT(r.frames_on_impassable, 0u);
    } else {
      EXPECT_EQ(r.outcome, loops::NavigateOutcome::kUnreachable) << r.reason;
      EXPECT_EQ(r.frames_on_impassable, 0u);
    }
  }
}

// The goal is north-east, so the first plan turns left at once, across the rock's cells. Without
// the approach the rock is unseen and the footprint crosses it; with the last 2 m driven to the
// start swept into the map, the plan keeps off it.
TEST(NavigateStart, ApproachSweepsShowARockInTheBlindDisk) {
  const sim::Scene scene = rock_beside_start();
  const Pose2 start{10, 10, 0}, goal{13, 15, std::numbers::pi / 2};
  loops::NavigateConfig cfg;
  for (double approach : {0.0, 2.0}) {
    cfg.approach_m = approach;
    const auto r = loops::run_navigate(scene, SensorModel::vlp16(), start, goal, cfg);
    std::printf(
        "approach %.1f m: %s (%s), %zu approach sweeps, ratio %.3f, %zu frames on "
        "impassable (%.2f m deep), %zu on the rock (least gap %.2f m), %.1f s wall\n",
        approach, loops::to_string(r.outcome), r.reason.c_str(), r.approach_sweeps, r.length_ratio,
        r.frames_on_impassable, r.max_impassable_depth_m, r.frames_on_obstacles,
        r.min_obstacle_gap_m, r.wall_s);
    EXPECT_EQ(r.max_impassable_depth_m > 0.0, r.frames_on_impassable > 0u);
    double deepest_row = 0.0;  // the log's rows carry the depth, gap and tilt of each period
    double nearest_row = INFINITY, tilt_row = 0.0;
    std::size_t on_rock_rows = 0;
    for (const auto& row : r.rows) {
      if (!row.footprint_on_impassable) {
        EXPECT_EQ(row.impassable_depth_m, 0.0);
        EXPECT_GE(row.obstacle_gap_m, 0.0);  // on the rock is on its cells
      }
      deepest_row = std::max(deepest_row, row.impassable_depth_m);
      nearest_row = std::min(nearest_row, row.obstacle_gap_m);
      on_rock_rows += row.obstacle_gap_m < 0.0;
      tilt_row = std::max(tilt_row, row.tilt_deg);
      EXPECT_FALSE(row.tilted_over);  // flat ground
    }
    EXPECT_EQ(deepest_row, r.max_impassable_depth_m);
    EXPECT_EQ(nearest_row, r.min_obstacle_gap_m);
    EXPECT_EQ(on_rock_rows, r.frames_on_obstacles);
    EXPECT_EQ(tilt_row, r.max_tilt_deg);
    EXPECT_LT(r.max_tilt_deg, 1.0);
    if (approach == 0.0) {
      EXPECT_EQ(r.approach_sweeps, 0u);
      EXPECT_GT(r.frames_on_impassable, 0u);
      EXPECT_GT(r.frames_on_obstacles, 0u);  // on the rock itself, not only on its cells
      EXPECT_LT(r.min_obstacle_gap_m, 0.0);
      // Across the rock: its cells reach well into the footprint (at most its half width).
      EXPECT_GE(r.max_impassable_depth_m, 0.1);
      EXPECT_LE(r.max_impassable_depth_m, 0.29);
    } else {
      EXPECT_EQ(r.approach_sweeps, 4u);
      EXPECT_EQ(r.outcome, loops::NavigateOutcome::kArrived) << r.reason;
      EXPECT_EQ(r.frames_on_impassable, 0u);
      EXPECT_EQ(r.frames_on_obstacles, 0u);
      EXPECT_GT(r.min_obstacle_gap_m, 0.0);
      EXPECT_LE(r.length_ratio, 1.15);
    }
  }
}

// A robot standing 0.1 m from a blocked cell on its left: the planner's inflated footprint
// touches it, the exact one does not. The escape is a short move, each pose of which keeps the
// exact footprint off the blocked cell, ending on a pose the planner calls free; with blocked
// cells on every side within reach there is none.
TEST(NavigateStart, EscapeLeavesAPoseBesideAnObstacle) {
  Grid2D grid(GridGeometry{0.1, {0, 0}, 60, 40});
  auto tau = grid.add_layer(terrain::layer::kTraversability, 1.f);
  grid.add_layer(terrain::layer::kPoints, 10.f);
  const GridGeometry& g = grid.geometry();
  auto block = [&](int ix, int iy) { tau[g.linear_index(ix, iy)] = 0.f; };
  // The robot at (3, 2) heading east (x 2.535-3.465, y 1.71-2.29); a rock at x 2.8-3.2,
  // y 2.3-2.4.
  for (int ix = 28; ix < 32; ++ix) block(ix, 23);
  terrain::RobotConfig robot;
  planning::MapReadConfig read;
  const Pose2 from{3.0, 2.0, 0.0};
  {
    const planning::PlanningMap map(grid, robot, read);
    ASSERT_FALSE(map.pose_free(from));
    const auto blocked = loops::known_blocked(grid);
    const auto standing = loops::footprint_cells(g, from, robot);
    EXPECT_FALSE(loops::footprint_enters_blocked(g, blocked, standing, from, robot));
    const auto out = loops::escape_path(map, blocked, from, false, 1.0);
    ASSERT_TRUE(out.has_value());
    EXPECT_LE(planning::path_length_m(*out), 1.0 + 1e-9);
    EXPECT_TRUE(map.pose_free(out->back().pose));
    for (const auto& p : *out)
      EXPECT_FALSE(loops::footprint_enters_blocked(g, blocked, standing, p.pose, robot));
    std::printf("escape: %zu poses, %.2f m, to (%.2f, %.2f, %.2f)\n", out->size(),
                planning::path_length_m(*out), out->back().pose.x_m, out->back().pose.y_m,
                out->back().pose.yaw_rad);
  }
  // Walled in 0.1 m from the footprint on every side: no escape.
  for (int ix = 20; ix < 40; ++ix) block(ix, 16), block(ix, 23);
  for (int iy = 16; iy < 24; ++iy) block(24, iy), block(35, iy);
  const planning::PlanningMap map(grid, robot, read);
  EXPECT_FALSE(loops::escape_path(map, loops::known_blocked(grid), from, false, 1.0).has_value());
}

// A robot switched on where it stands (no approach) 1.5 m before a trench it cannot see (in the
// blind disk, its far bank level with the robot: no rule marks it), the goal beyond. Without the
// tilt stop it drives through the trench; with it the robot stops as its front tips down the
// wall, takes the cells under its front as impassable and plans again from there. Measured 82
// frames without, 75 with (the chassis tilted 51.8 and 32.4 deg at most); 113 and 55 while the
// loop levelled its sweeps to the far ground (loops::navigate_fusion_config): tipped into the
// trench, the robot's own frame is the trench wall's, and the far bank seen from it lies higher
// than level.
TEST(NavigateStart, TiltStopEndsADriveIntoAHiddenTrench) {
  const sim::Scene scene = trench_ahead(1.5, 3.0);
  loops::NavigateConfig cfg;
  cfg.approach_m = 0.0;
  std::size_t frames_without = 0;
  for (double tilt : {0.0, cfg.tilt_stop_deg}) {
    cfg.tilt_stop_deg = tilt;
    const auto r = loops::run_navigate(scene, SensorModel::vlp16(), {10, 10, 0}, {20, 10, 0}, cfg);
    std::printf(
        "tilt stop %.0f deg: %s (%s), %d tilt stops, %zu frames on impassable, tilted %.1f deg\n",
        tilt, loops::to_string(r.outcome), r.reason.c_str(), r.tilt_stops, r.frames_on_impassable,
        r.max_tilt_deg);
    EXPECT_EQ(r.truth_status, planning::PlanStatus::kSuccess);
    EXPECT_EQ(r.outcome, loops::NavigateOutcome::kArrived) << r.reason;
    EXPECT_GT(r.max_tilt_deg, 30.0);  // the front tipped down the trench's wall
    // ... down to the trench's floor without the stop (51.8 deg measured), only past the limit
    // with it (32.4 deg).
    EXPECT_GE(r.max_tilt_deg, tilt == 0.0 ? 45.0 : 30.0);
    EXPECT_LE(r.max_tilt_deg, tilt == 0.0 ? 60.0 : 35.0);
    if (tilt == 0.0) {
      EXPECT_EQ(r.tilt_stops, 0);
      EXPECT_GT(r.frames_on_impassable, 75u);  // 82 measured
      frames_without = r.frames_on_impassable;
    } else {
      EXPECT_GE(r.tilt_stops, 1);
      EXPECT_LE(r.frames_on_impassable, 80u);  // 75 measured
      EXPECT_LT(r.frames_on_impassable, frames_without);
    }
  }
}

// A robot in a lane 3.9 m wide (a 1 m wall 2 m to its right, a 0.6 m ditch 1.9 m to its left),
// its goal 6 m behind it facing back: it must turn in the lane. The ground between it and the
// ditch lies in its blind disk and the ditch's far bank is the first ground its rays meet there,
// lower than the robot: blind drops mark the band, which leaves the lane too narrow for a turn.
// Reported unreachable without a look; with one (NavigateConfig::guess_looks) the robot goes to
// see the band from beyond its blind disk, finds the turn and arrives, on no truth-impassable
// cell either way. Ground driven over keeps its guesses here (NavigateConfig::
// driven_clears_guesses false): with the cells it has driven over taken as no guess, the robot
// turns in the lane without a look (13.3 m driven, measured).
TEST(NavigateStart, LookAtBlindDropsBeforeGivingUp) {
  const sim::Scene scene = lane_beside_ditch();
  const Pose2 start{10, 10, 0}, goal{4, 10, std::numbers::pi};
  loops::NavigateConfig cfg;
  cfg.driven_clears_guesses = false;
  for (int looks : {0, cfg.guess_looks}) {
    cfg.guess_looks = looks;
    const auto r = loops::run_navigate(scene, SensorModel::vlp16(), start, goal, cfg);
    std::printf("%d looks allowed: %s (%s), %d taken, %zu frames on impassable, %.1f m driven\n",
                looks, loops::to_string(r.outcome), r.reason.c_str(), r.guess_looks,
                r.frames_on_impassable, r.driven_length_m);
    EXPECT_EQ(r.truth_status, planning::PlanStatus::kSuccess);
    EXPECT_EQ(r.frames_on_impassable, 0u);
    if (looks == 0) {
      EXPECT_EQ(r.outcome, loops::NavigateOutcome::kUnreachable) << r.reason;
      EXPECT_EQ(r.guess_looks, 0);
    } else {
      EXPECT_EQ(r.outcome, loops::NavigateOutcome::kArrived) << r.reason;
      EXPECT_GE(r.guess_looks, 1);
      EXPECT_LT(r.driven_length_m, 30.0);  // 19.3 m measured (25.7 m when first written)
    }
  }
}
