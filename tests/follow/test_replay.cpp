// FollowReplay on synthetic 2D scans: an operator walks away from a standing robot, the robot
// then drives after them (its motion given as recorded odometry) and closes in on the operator
// who stops; the replay chooses the target, holds it, follows, and stops too close.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "fieldlidar/follow/replay.hpp"
#include "synthetic_scan.hpp"

namespace fieldlidar {
namespace {

/// A one-ring cloud (ring 0, z = 0) from points in beam order.
PointCloud scan_cloud(const std::vector<Eigen::Vector2d>& pts) {
  PointCloud c;
  c.fields.ring = true;
  for (const auto& p : pts) {
    Point q;
    q.x = float(p.x()), q.y = float(p.y()), q.z = 0.f, q.ring = 0;
    c.push_back(q);
  }
  c.width = std::uint32_t(c.size()), c.height = 1;
  return c;
}

TEST(FollowReplay, SyntheticOperatorWalkedAfterThenTooClose) {
  const double period = 0.1;
  follow::ReplayConfig cfg;
  follow::FollowReplay replay(*SensorModel::preset("vlp16"), cfg);
  std::vector<follow::FollowState> states;
  double robot_x = 0, person_x = 1.8, path_m = 0;
  for (int k = 0; k < 120; ++k) {
    const double t = k * period;
    // 0-3 s the robot stands and the operator walks off at 1 m/s; 3-7 s both move at 1 m/s;
    // from 7 s the operator slows to 0.5 m/s and the robot closes in at 1.4 m/s to 0.9 m
    // behind them, then keeps that distance.
    const double v_person = t < 7 ? 1.0 : 0.5;
    double v_robot = t < 3 ? 0.0 : (t < 7 ? 1.0 : 1.4);
    if (k > 0) {
      person_x += v_person * period;
      v_robot = std::min(v_robot, (person_x - 0.9 - robot_x) / period);
      robot_x += v_robot * period;
      path_m += v_robot * period;
    }
    // Legs 0.2 m apart, swinging +-0.15 m along the walk at 1 Hz while walking.
    const double swing = v_person > 0 ? 0.15 * std::sin(2 * M_PI * t) : 0.0;
    const double rel = person_x - robot_x;
    std::vector<test::Circle> legs = {{{rel + swing, 0.1}, 0.06}, {{rel - swing, -0.1}, 0.06}};
    const std::vector<test::Wall> walls = {{{-20 - robot_x, 4}, {60 - robot_x, 4}},
                                           {{-20 - robot_x, -4}, {60 - robot_x, -4}}};
    const auto cloud = scan_cloud(test::cast_scan(legs, walls));
    const auto f = replay.step(cloud, 100.0 + t, make_pose(robot_x, 0, 0, 0, 0, 0));
    states.push_back(f.output.control.state);
  }
  const auto& s = replay.summary();
  EXPECT_EQ(s.frames, 120u);
  EXPECT_NEAR(s.path_length_m, path_m, 1e-6);
  ASSERT_TRUE(s.first_target_id);
  EXPECT_EQ(s.target_switches, 0u);
  EXPECT_EQ(s.distinct_target_ids, 1u);
  // Measured: chosen after 13 scans (the leg pipeline reports a person once it has walked 1 m),
  // then held in every scan (1.00), 95 scans following, 12 too close, none lost.
  EXPECT_LE(s.frames - s.frames_with_target_chosen, 15u);
  EXPECT_GE(s.target_held_fraction(), 0.98);
  EXPECT_GE(s.frames_following, 90u);
  EXPECT_EQ(s.frames_by_state[std::size_t(follow::FollowState::kLost)], 0u);
  // The last second: nearer than L_s = 1.2 m, the mower would stop.
  EXPECT_EQ(states.back(), follow::FollowState::kTooClose);
  EXPECT_GE(s.frames_by_state[std::size_t(follow::FollowState::kTooClose)], 10u);
  EXPECT_EQ(s.stops, 1u);
  EXPECT_EQ(s.frames_by_state[std::size_t(follow::FollowState::kTooFar)], 0u);
}

TEST(FollowReplay, PlanarScanAndRings) {
  PointCloud flat;
  Point p;
  p.x = 1, p.y = 2, p.z = 0;
  flat.push_back(p);
  EXPECT_TRUE(follow::is_planar_scan(flat));  // no ring field, z = 0
  p.z = 0.5f;
  flat.push_back(p);
  EXPECT_FALSE(follow::is_planar_scan(flat));
}

}  // namespace
}  // namespace fieldlidar
