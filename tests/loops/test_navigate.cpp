// The navigate loop (seed 004 closed loop) on short drives of the simulated terrain scene of seed
// 0: the robot maps, plans, follows and arrives, its footprint never on a truth-impassable cell,
// its driven length within 1.15 x the Hybrid A* path planned on the truth map.
#include <cmath>
#include <cstdio>
#include <numbers>

#include <gtest/gtest.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/loops/navigate.hpp"
#include "fieldlidar/sim/scenes.hpp"

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
  loops::NavigateConfig bad;
  bad.fusion.layers.robot.min_turn_radius_m = 0.0;
  EXPECT_THROW(loops::run_navigate(scene0(), SensorModel::vlp16(), {3, 20, 0}, {8, 20, 0}, bad),
               Error);
}
