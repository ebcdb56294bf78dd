// The path follower on exact unicycle motion: it tracks a forward arc and a path with a reverse
// run (a cusp) within a few centimetres, stops at the cusp and at the end, and never commands a
// curvature above 1 / R_min or a speed above its limits.
#include <cmath>
#include <cstdio>
#include <numbers>

#include <gtest/gtest.h>

#include "fieldlidar/planning/path_follower.hpp"
#include "fieldlidar/planning/reeds_shepp.hpp"

using namespace fieldlidar::planning;

namespace {

struct Drive {
  double max_cross_track_m = 0, max_kappa = 0, max_speed = 0, max_reverse_speed = 0;
  int stops_moving = 0;  ///< times the speed passed through zero between two runs
  Pose2 end;
  bool done = false;
};

Drive drive(const Path& path, const FollowerConfig& cfg, double max_time_s = 120) {
  PathFollower f(cfg);
  f.set_path(path);
  Drive d;
  Pose2 p = path.front().pose;
  double v = 0;
  for (double t = 0; t < max_time_s; t += 0.1) {
    const DriveCommand c = f.command(p, v, 0.1);
    d.max_cross_track_m = std::max(d.max_cross_track_m, c.cross_track_m);
    if (std::abs(c.v_m_s) > 1e-6)
      d.max_kappa = std::max(d.max_kappa, std::abs(c.yaw_rate_rad_s / c.v_m_s));
    d.max_speed = std::max(d.max_speed, c.v_m_s);
    d.max_reverse_speed = std::max(d.max_reverse_speed, -c.v_m_s);
    if ((v > 0 && c.v_m_s < 0) || (v < 0 && c.v_m_s > 0)) ++d.stops_moving;
    p = integrate_unicycle(p, c.v_m_s, c.yaw_rate_rad_s, 0.1);
    v = c.v_m_s;
    if (c.done && v == 0) {
      d.done = true;
      break;
    }
  }
  d.end = p;
  return d;
}

}  // namespace

TEST(PathFollower, TracksAForwardReedsSheppCurve) {
  const Pose2 a{0, 0, 0}, b{8, 4, std::numbers::pi / 2};
  const Path path = rs_sample(a, reeds_shepp(a, b, 1.0), 1.0, 0.1);
  const Drive d = drive(path, {});
  ASSERT_TRUE(d.done);
  // Pure pursuit at 0.6 m look-ahead and R_min = 1 m leaves the heading 0.155 rad off at the end
  // (measured), and the position within a few centimetres.
  std::printf("cross-track max %.3f m, end %.3f m / %.3f rad off\n", d.max_cross_track_m,
              std::hypot(d.end.x_m - b.x_m, d.end.y_m - b.y_m),
              std::abs(wrap_angle(d.end.yaw_rad - b.yaw_rad)));
  EXPECT_LT(d.max_cross_track_m, 0.12);
  EXPECT_LT(std::hypot(d.end.x_m - b.x_m, d.end.y_m - b.y_m), 0.1);
  EXPECT_LT(std::abs(wrap_angle(d.end.yaw_rad - b.yaw_rad)), 0.2);
  EXPECT_LE(d.max_kappa, 1.0 + 1e-9);
  EXPECT_LE(d.max_speed, 1.0 + 1e-9);
}

TEST(PathFollower, StopsAtTheCuspAndBacksUp) {
  // A parallel-parking move: the shortest curve has a reverse run.
  const Pose2 a{0, 0, 0}, b{0, 1.5, 0};
  const RsCurve curve = reeds_shepp(a, b, 1.0);
  const Path path = rs_sample(a, curve, 1.0, 0.1);
  ASSERT_GE(direction_changes(path), 1);
  FollowerConfig cfg;
  const Drive d = drive(path, cfg);
  ASSERT_TRUE(d.done);
  EXPECT_GE(d.stops_moving, 1);
  EXPECT_LT(d.max_cross_track_m, 0.15);
  EXPECT_LT(std::hypot(d.end.x_m - b.x_m, d.end.y_m - b.y_m), 0.15);
  EXPECT_LE(d.max_kappa, 1.0 + 1e-9);
  EXPECT_LE(d.max_reverse_speed, cfg.max_reverse_speed_m_s + 1e-9);
}

TEST(PathFollower, NoPathMeansStandStill) {
  PathFollower f;
  const DriveCommand c = f.command({}, 0.5, 0.1);
  EXPECT_TRUE(c.done);
  EXPECT_NEAR(c.v_m_s, 0.42, 1e-9);  // braking at 0.8 m/s^2
}
