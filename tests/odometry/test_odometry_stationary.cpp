// A robot standing still with IMU and wheels (OdometryConfig::stationary_m): the pose is kept,
// not re-matched every sweep.

#include <gtest/gtest.h>

#include "odometry_eval.hpp"

namespace fieldlidar::odometry::test {
namespace {

/// 30 sweeps of the greenhouse from the start of its route, the robot standing there.
SimSequence standing_sequence() {
  const sim::Scene scene = sim::make_scene(sim::SceneKind::kGreenhouse, 0);
  const auto motion = sim::drive_scene_route(scene, 1.0);
  const Pose T_world_base = motion.base_pose_fn()(0.0);
  const std::function<Pose(double)> base = [T_world_base](double) { return T_world_base; };
  SimSequence s;
  s.sensor = SensorModel::vlp16();
  s.T_base_lidar = motion.T_base_lidar();
  const Pose T_world_lidar = T_world_base * s.T_base_lidar;
  sim::SimConfig cfg;
  cfg.seed = 3;
  const sim::LidarSimulator simulator(scene, s.sensor, cfg);
  const double period = s.sensor.sweep_period_s();
  for (int i = 0; i < 30; ++i) {
    auto f = simulator.scan(i * period, [&](double) { return T_world_lidar; });
    f.cloud.stamp_s = f.stamp_s;
    s.frames.push_back(std::move(f.cloud));
    s.truth.push_back(T_world_lidar);
  }
  for (const auto& m : sim::simulate_imu(base, 0.0, 30 * period, {.seed = 7}))
    s.imu.push_back({m.stamp_s, m.gyro_rad_s, m.accel_m_s2});
  for (const auto& m : sim::simulate_wheel_odometry(base, 0.0, 30 * period, {.seed = 11}))
    s.wheels.push_back({m.stamp_s, m.linear_m_s, m.yaw_rate_rad_s});
  return s;
}

/// Largest sweep-to-sweep translation of the estimate (m).
double largest_step(const std::vector<Pose>& poses) {
  double out = 0;
  for (std::size_t i = 1; i < poses.size(); ++i)
    out = std::max(out, (poses[i].translation() - poses[i - 1].translation()).norm());
  return out;
}

TEST(OdometryStationary, StandingRobotKeepsItsPose) {
  const auto s = standing_sequence();
  OdometryConfig hold;
  hold.stationary_m = 0.002;
  std::vector<OdometryResult> held;
  const auto poses = run(s, hold, true, &held);
  for (std::size_t i = 1; i < held.size(); ++i) {
    EXPECT_TRUE(held[i].stationary) << i;
    EXPECT_TRUE(held[i].registered) << i;
  }
  EXPECT_FALSE(held[0].stationary);
  // The prior from the noisy IMU and wheels alone: well under a millimetre per sweep.
  EXPECT_LT(largest_step(poses), 0.001);
  // Matched every sweep instead, the pose moves with the range noise.
  OdometryConfig matched;
  matched.stationary_m = 0;
  std::vector<OdometryResult> moving;
  const auto jittered = run(s, matched, true, &moving);
  for (const auto& r : moving) EXPECT_FALSE(r.stationary);
  std::printf("largest step per sweep: held %.4f m, matched %.4f m\n", largest_step(poses),
              largest_step(jittered));
}

// Without wheel speeds the IMU alone does not say the robot stands: every sweep is matched.
TEST(OdometryStationary, ImuAloneDoesNotHold) {
  auto s = standing_sequence();
  s.wheels.clear();
  OdometryConfig hold;
  hold.stationary_m = 0.002;
  std::vector<OdometryResult> res;
  run(s, hold, true, &res);
  for (const auto& r : res) EXPECT_FALSE(r.stationary);
}

}  // namespace
}  // namespace fieldlidar::odometry::test
