// Where the lowest beam meets the ground (loops::blind_range_m): a level mount's blind disk, the
// same on a robot tilted with its ground, and a mount pitched forward on the robot, which sees
// the ground nearer ahead and farther behind.
#include <cmath>

#include <gtest/gtest.h>

#include "fieldlidar/loops/navigate_maps.hpp"

using namespace fieldlidar;

namespace {

constexpr double kMast = 1.2, kBlind = 4.5;  // a VLP-16 on a 1.2 m mast: lowest beam 14.9 deg

loops::AreaGridRules level_rules() {
  loops::AreaGridRules r;
  r.sensor_height_m = kMast;
  r.blind_radius_m = kBlind;
  return r;
}

Eigen::Vector2d direction(double deg) {
  return {std::cos(deg * M_PI / 180.0), std::sin(deg * M_PI / 180.0)};
}

}  // namespace

TEST(BlindRange, LevelMountIsTheBlindDiskInEveryDirection) {
  const auto r = level_rules();
  for (double a = -180; a < 180; a += 15)
    EXPECT_NEAR(loops::blind_range_m(r, direction(a)), kBlind, 1e-9) << a;
}

TEST(BlindRange, RobotTiltedWithItsGroundKeepsTheDisk) {
  auto r = level_rules();
  // 15 deg of roll and pitch: the sensor's z axis and the ground's normal lean alike.
  const Eigen::Vector3d n =
      (Eigen::AngleAxisd(0.26, Eigen::Vector3d::UnitX()) *
       Eigen::AngleAxisd(0.26, Eigen::Vector3d::UnitY()) * Eigen::Vector3d::UnitZ());
  r.ground_normal = n;
  r.sensor_up = n;
  for (double a = -180; a < 180; a += 15)
    EXPECT_NEAR(loops::blind_range_m(r, direction(a)), kBlind, 1e-9) << a;
}

TEST(BlindRange, PitchedMountSeesNearerAheadAndFartherBehind) {
  auto r = level_rules();
  // The robot faces +x, its LiDAR pitched 10 deg nose down: its z axis leans forward.
  const double pitch = 10.0 * M_PI / 180.0;
  r.sensor_up = Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) * Eigen::Vector3d::UnitZ();
  const double lowest = std::atan2(kMast, kBlind);
  EXPECT_NEAR(loops::blind_range_m(r, direction(0)), kMast / std::tan(lowest + pitch), 1e-9);
  EXPECT_NEAR(loops::blind_range_m(r, direction(180)), kMast / std::tan(lowest - pitch), 1e-9);
  EXPECT_NEAR(loops::blind_range_m(r, direction(90)), kBlind, 1e-9);
  EXPECT_LT(loops::blind_range_m(r, direction(0)), 2.7);   // 2.6 m ahead
  EXPECT_GT(loops::blind_range_m(r, direction(180)), 13);  // 13.8 m behind
  // Pitched past the lowest beam, it never meets the ground behind.
  r.sensor_up = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()) * Eigen::Vector3d::UnitZ();
  EXPECT_TRUE(std::isinf(loops::blind_range_m(r, direction(180))));
  // No sensor height or no blind radius: no blind range.
  r.blind_radius_m = 0;
  EXPECT_EQ(loops::blind_range_m(r, direction(0)), 0.0);
}
