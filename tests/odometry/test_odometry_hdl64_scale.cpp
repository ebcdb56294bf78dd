// Scale of the odometry on 64-beam sweeps at car speed, against simulated truth. On
// kitti_tracking0000 the estimated path is 0.971-0.972 of the stereo ORB-SLAM3 reference's
// with every setting tried; these drives tell whether the odometry itself shortens a path
// driven like that one (18 m in 5 s, turning 38 deg, HDL-64E, LiDAR only).

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>

#include <gtest/gtest.h>

#include "odometry_eval.hpp"

namespace fieldlidar::odometry::test {
namespace {

constexpr double kPi = std::numbers::pi;

/// 50 HDL-64E sweeps from the start of the scene's route, forward at `speed_m_s` while turning
/// at `yaw_rate_deg_s`, noise seed 1. `kitti_like`: every sweep taken from its start pose and
/// without per-point time (a motion-compensated sweep, as KITTI's behave); else skewed by the
/// motion and carrying each point's time.
SimSequence car_drive(sim::SceneKind kind, bool kitti_like, double speed_m_s = 3.6,
                      double yaw_rate_deg_s = 7.7) {
  SimSequence s;
  s.sensor = SensorModel::hdl64e();
  const sim::Scene scene = sim::make_scene(kind, 0);
  const Pose start = sim::drive_scene_route(scene, 1.0).T_world_lidar(0.0);
  const double yaw_rate = yaw_rate_deg_s * kPi / 180;
  const std::function<Pose(double)> pose = [=](double t) {
    // On a circle of radius v / w: the heading follows the path.
    const double a = yaw_rate * t, r = speed_m_s / yaw_rate;
    return start * make_pose(r * std::sin(a), r * (1 - std::cos(a)), 0, 0, 0, a);
  };
  const double period = s.sensor.sweep_period_s();
  sim::SimConfig cfg;
  cfg.seed = 1;
  const sim::LidarSimulator simulator(scene, s.sensor, cfg);
  for (int i = 0; i < 50; ++i) {
    const double t0 = i * period;
    auto f = kitti_like ? simulator.scan(t0, pose(t0)) : simulator.scan(t0, pose);
    f.cloud.stamp_s = t0;
    // STRIPTIME: skewed sweeps without their times too (then timed from the azimuth, AZPERIOD).
    if (kitti_like || std::getenv("STRIPTIME")) f.cloud.fields.time = false;
    s.frames.push_back(std::move(f.cloud));
    s.truth.push_back(f.T_world_lidar_start);
  }
  for (const auto& m : sim::simulate_imu(pose, 0.0, 50 * period + 0.2, {.seed = 7}))
    s.imu.push_back({m.stamp_s, m.gyro_rad_s, m.accel_m_s2});
  for (const auto& m : sim::simulate_wheel_odometry(pose, 0.0, 50 * period + 0.2, {.seed = 11}))
    s.wheels.push_back({m.stamp_s, m.linear_m_s, m.yaw_rate_rad_s});
  return s;
}

TrajectoryErrors run_drive(const SimSequence& s, const char* what) {
  OdometryConfig cfg;
  apply_env(cfg);  // tuning knobs, none set in a test run
  const auto est = run(s, cfg, std::getenv("STREAMS") != nullptr);
  const auto e = trajectory_errors(est, relative_to_first(s.truth), 5.0);
  std::printf(
      "%-34s path %.3f of %.3f m (%.4f)  RPE %.2f cm / %.3f deg  ATE %.3f m (Sim3 %.3f m)\n", what,
      e.est_path_m, e.path_m, e.est_path_m / e.path_m, 100 * e.rpe_t_m, e.rpe_r_deg, e.ate_se3_m,
      e.ate_sim3_m);
  return e;
}

// Figures (path / truth, RPE per frame), LiDAR only, constant-velocity de-skew:
//   compensated sweeps without times: forest 0.9970, 0.64 cm; terrain 1.0019, 0.42 cm; lawn
//   0.9992, 0.89 cm: the odometry itself does not shorten the path. Timed from the azimuth
//   (AZPERIOD=0.1), which de-skews sweeps that need none: 0.93 / 0.74 / 1.46 cm, rotation
//   0.021 / 0.032 / 0.079 deg against 0.012 / 0.012 / 0.045.
//   skewed sweeps with times: forest 0.9971, 0.58 cm; terrain 1.0017, 0.48 cm; lawn 0.9996,
//   1.08 cm; the same timed from the azimuth. Before the map's start-up was de-skewed
//   (deskew_restart.cpp) 0.9860 / 3.36 cm, 0.9915 / 2.94, 0.9896 / 2.92; after it, with the
//   last motion alone (LASTVEL=1, DeskewConfig::velocity_from_two_sweeps) 1.20 / 0.63 / 1.50 cm.
//   With IMU + wheels (STREAMS=1) 0.61 / 0.53 / 1.11 cm; not de-skewed 0.58 / 0.45 / 0.83 cm.
TEST(OdometryHdl64Scale, DISABLED_Report) {
  // Not the greenhouse: at car speed across its rows the sensor drives through the plants.
  const char* only = std::getenv("SKEWED");  // 1: skewed sweeps only, 0: compensated only
  for (auto kind : {sim::SceneKind::kForest, sim::SceneKind::kTerrain, sim::SceneKind::kLawn}) {
    for (bool kitti_like : {true, false}) {
      if (only && (std::atoi(only) == 1) == kitti_like) continue;
      const std::string what =
          sim::to_string(kind) + (kitti_like ? ", compensated" : ", skewed + time");
      run_drive(car_drive(kind, kitti_like), what.c_str());
    }
  }
}

// Skewed sweeps at car speed, de-skewed by the constant velocity: the map's start-up no longer
// leaves the path short and the velocity no longer rings (before: path 0.986 of the truth's, RPE
// 3.36 cm / 0.075 deg; now 0.9971, 0.58 cm / 0.016 deg).
TEST(OdometryHdl64Scale, SkewedSweepsAtCarSpeedKeepTheScale) {
  const auto e = run_drive(car_drive(sim::SceneKind::kForest, false), "forest, skewed + time");
  EXPECT_NEAR(e.est_path_m / e.path_m, 1.0, 0.006);
  EXPECT_LT(e.rpe_t_m, 0.009);
  EXPECT_LT(e.rpe_r_deg, 0.025);
  EXPECT_LT(e.ate_sim3_m, 0.012);
}

}  // namespace
}  // namespace fieldlidar::odometry::test
