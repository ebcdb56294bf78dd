#include <gtest/gtest.h>

#include <cmath>

#include "fieldlidar/follow/boundary.hpp"
#include "fieldlidar/follow/controller.hpp"

namespace fieldlidar::follow {
namespace {

TEST(Safety, SeedRuleOnTheDistance) {
  SafetyConfig c;
  c.safe_distance_m = 1.2;
  c.max_distance_m = 7.0;
  EXPECT_EQ(check_safety(Eigen::Vector2d(1.0, 0.5), c), FollowState::kTooClose);   // L = 1.118
  EXPECT_EQ(check_safety(Eigen::Vector2d(3.0, 4.0), c), FollowState::kFollowing);  // L = 5
  EXPECT_EQ(check_safety(Eigen::Vector2d(-6.0, 3.7), c), FollowState::kTooFar);    // L = 7.05
  EXPECT_EQ(check_safety(std::nullopt, c), FollowState::kLost);
  EXPECT_EQ(check_safety(Eigen::Vector2d(NAN, 1.0), c), FollowState::kLost);
}

TEST(WheelCommand, SeedFormulas) {
  DriveConfig d;
  d.gear_ratio = 30;
  d.wheel_diameter_m = 0.2;
  const auto c = make_wheel_command(0.5, 0.2, d);
  EXPECT_DOUBLE_EQ(c.left_m_s, 0.4);
  EXPECT_DOUBLE_EQ(c.right_m_s, 0.6);
  EXPECT_DOUBLE_EQ(c.left_motor_rev_s, 0.4 * 30 / (M_PI * 0.2));
  EXPECT_DOUBLE_EQ(c.right_motor_rev_s, 0.6 * 30 / (M_PI * 0.2));
  EXPECT_FALSE(make_wheel_command(0, 0, d).moving());
}

TEST(PredictPose, StraightAndQuarterCircle) {
  const Pose2 p{1, 2, 0};
  const auto s = predict_pose(p, 0.5, 0, 0.4, 2);
  EXPECT_NEAR(s.x_m, 2, 1e-12);
  EXPECT_NEAR(s.y_m, 2, 1e-12);
  // omega = dv / b = 0.5 rad/s, radius v / omega = 2 m; a quarter turn takes pi s.
  const auto q = predict_pose(p, 1.0, 0.2, 0.4, M_PI);
  EXPECT_NEAR(q.x_m, 3, 1e-9);
  EXPECT_NEAR(q.y_m, 4, 1e-9);
  EXPECT_NEAR(q.yaw_rad, M_PI / 2, 1e-12);
}

Trail straight_trail() {
  Trail t(0.1);
  for (int i = 0; i <= 100; ++i) t.add({0.1 * i, 0});
  return t;
}

TEST(Trail, SpacingAndProjection) {
  Trail t(0.25);
  t.add({0, 0});
  t.add({0.1, 0});  // too near
  t.add({0.3, 0});
  t.add({0.3, 0.3});
  ASSERT_EQ(t.points().size(), 3u);
  const auto pr = t.project({0.15, 0.05});
  ASSERT_TRUE(pr.valid);
  EXPECT_NEAR(pr.lateral_m, 0.05, 1e-12);  // left of the trail is positive
  EXPECT_NEAR(pr.heading_rad, 0, 1e-12);
  EXPECT_NEAR(pr.along_m, 0.15, 1e-12);
  const auto pr2 = t.project({0.4, 0.2});
  EXPECT_NEAR(pr2.lateral_m, -0.1, 1e-12);  // right of the northbound segment
  EXPECT_NEAR(pr2.heading_rad, M_PI / 2, 1e-12);
}

TEST(ChooseDv, SteersBackToTheTrailSymmetrically) {
  const auto trail = straight_trail();
  DriveConfig d;
  EXPECT_NEAR(choose_dv({1, 0, 0}, 0.8, trail, d), 0.0, 1e-3);
  const double left = choose_dv({1, 0.5, 0}, 0.8, trail, d);
  const double right = choose_dv({1, -0.5, 0}, 0.8, trail, d);
  EXPECT_LT(left, -0.05);  // left of the trail: turn right (v_r < v_l)
  EXPECT_NEAR(left, -right, 0.01);
  // Heading away from the trail direction: turn back.
  EXPECT_GT(choose_dv({1, 0, -0.5}, 0.8, trail, d), 0.05);
}

TEST(Controller, SafetyStopsBothWheelsAtOnceAndAccelerationIsLimited) {
  DriveConfig d;
  SafetyConfig s;
  FollowController c(d, s);
  auto trail = straight_trail();
  const Pose2 mower{0, 0, 0};
  auto out = c.step(mower, Eigen::Vector2d(5, 0), trail, 0.1);
  EXPECT_EQ(out.state, FollowState::kFollowing);
  EXPECT_NEAR(out.command.v_m_s, d.max_accel_m_s2 * 0.1, 1e-9);  // from rest
  for (int i = 0; i < 20; ++i) out = c.step(mower, Eigen::Vector2d(5, 0), trail, 0.1);
  EXPECT_NEAR(out.command.v_m_s, d.max_speed_m_s, 1e-9);  // v = gain * (5 - 2.2) > max
  out = c.step(mower, Eigen::Vector2d(1.0, 0), trail, 0.1);
  EXPECT_EQ(out.state, FollowState::kTooClose);
  EXPECT_EQ(out.command.left_m_s, 0.0);
  EXPECT_EQ(out.command.right_m_s, 0.0);
  out = c.step(mower, std::nullopt, trail, 0.1);
  EXPECT_EQ(out.state, FollowState::kLost);
  EXPECT_FALSE(out.command.moving());
  out = c.step(mower, Eigen::Vector2d(5, 0), trail, 0.1);  // resumes from rest
  EXPECT_NEAR(out.command.v_m_s, d.max_accel_m_s2 * 0.1, 1e-9);
}

/// Kinematic loop without perception: the operator walks a 10 m square at 1 m/s, the target is
/// known exactly; the mower must pass the corners, not cut them.
TEST(Controller, FollowsTheTrailAroundRightAngleCornersWithoutCuttingThem) {
  const std::vector<Eigen::Vector2d> square{{0, 0}, {10, 0}, {10, 10}, {0, 10}};
  auto person_at = [&](double s) {
    s = std::fmod(s, 40.0);
    const int e = int(s / 10);
    const Eigen::Vector2d a = square[std::size_t(e)], b = square[std::size_t((e + 1) % 4)];
    return Eigen::Vector2d(a + (b - a) * (s - 10 * e) / 10);
  };
  DriveConfig d;
  FollowController c(d, SafetyConfig{});
  Trail trail(d.trail_spacing_m);
  BoundaryRecorder rec;
  Pose2 m{0, 0, 0};
  const double dt = 0.1;
  double worst = 0;
  for (int k = 0; k < 600 && rec.length_m() < 38.0; ++k) {
    const Eigen::Vector2d person = person_at(3.0 + k * dt);
    trail.add(person);
    const Eigen::Vector2d rel = person - m.xy();
    const double cy = std::cos(m.yaw_rad), sy = std::sin(m.yaw_rad);
    const auto out = c.step(
        m, Eigen::Vector2d(cy * rel.x() + sy * rel.y(), -sy * rel.x() + cy * rel.y()), trail, dt);
    m = predict_pose(m, out.command.v_m_s, out.command.dv_m_s, d.track_width_m, dt);
    rec.record(m.xy(), out.state == FollowState::kFollowing);
    worst = std::max(worst, distance_to_closed(m.xy(), square));
  }
  // The mower has turned all four corners and is back near its start (the stop command).
  EXPECT_GE(rec.length_m(), 38.0);
  EXPECT_LT(worst, 0.25);
  const auto poly = rec.close();
  const auto err = compare_closed(poly.vertices, square);
  EXPECT_LT(err.mean_m, 0.05);
  EXPECT_LT(err.hausdorff_m, 0.3);
  EXPECT_TRUE(poly.self_intersections.empty());
}

}  // namespace
}  // namespace fieldlidar::follow
