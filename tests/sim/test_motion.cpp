// Motion during the sweep, robot trajectories, IMU and wheel odometry.

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "fieldlidar/sim/lidar_simulator.hpp"
#include "fieldlidar/sim/motion.hpp"
#include "fieldlidar/sim/scenes.hpp"
#include "sim_test_util.hpp"

namespace fieldlidar::sim {
namespace {

/// RMS distance of points to their least-squares plane (m).
double plane_rms(const std::vector<Eigen::Vector3d>& pts) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : pts) mean += p;
  mean /= double(pts.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& p : pts) cov += (p - mean) * (p - mean).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov / double(pts.size()));
  return std::sqrt(std::max(0.0, es.eigenvalues()(0)));
}

TEST(SimMotion, DeskewWithTheTrueTrajectoryRestoresAStaticWall) {
  Scene scene = test::flat_scene(0.0);
  const auto wall = make_label(LabelClass::kStructure);
  scene.add_mesh(make_aabb({10.0, -30.0, -0.5}, {10.5, 30.0, 6.0}, wall));
  const auto sensor = SensorModel::vlp16();
  SimConfig cfg;
  cfg.range_noise_m = 0.0;
  const LidarSimulator sim(scene, sensor, cfg);
  // Driving at 1.5 m/s while turning at 0.6 rad/s, sensor 1 m up.
  const auto motion = [](double t) { return make_pose(1.5 * t, 0.0, 1.0, 0, 0, 0.6 * t); };
  const double t0 = 0.0;
  const auto frame = sim.scan(t0, motion);
  const Pose T_start_inv = motion(t0).inverse();
  std::vector<Eigen::Vector3d> raw, deskewed;
  for (std::size_t i = 0; i < frame.cloud.size(); ++i) {
    if (frame.cloud.labels[i] != wall) continue;
    const auto& p = frame.cloud.points[i];
    const Eigen::Vector3d v(p.x, p.y, p.z);
    raw.push_back(v);
    deskewed.push_back(T_start_inv * motion(t0 + p.time) * v);
  }
  ASSERT_GT(raw.size(), 1000u);
  const double rms_raw = plane_rms(raw), rms_deskewed = plane_rms(deskewed);
  EXPECT_LT(rms_deskewed, 1e-3);  // float precision of a wall ~10 m away
  EXPECT_GT(rms_raw, 0.03);       // the uncorrected sweep is visibly bent
  // In the world, the de-skewed wall face is at x = 10 exactly.
  for (const auto& v : deskewed) EXPECT_NEAR((motion(t0) * v).x(), 10.0, 1e-3);
  // A fixed pose gives an unskewed wall.
  const auto still = sim.scan(t0, motion(t0));
  std::vector<Eigen::Vector3d> flat;
  for (std::size_t i = 0; i < still.cloud.size(); ++i)
    if (still.cloud.labels[i] == wall)
      flat.emplace_back(still.cloud.points[i].x, still.cloud.points[i].y, still.cloud.points[i].z);
  EXPECT_LT(plane_rms(flat), 1e-3);
}

TEST(SimMotion, ImuAtRestReadsGravityAndBias) {
  ImuConfig cfg;
  cfg.rate_hz = 200;
  const auto still = [](double) { return make_pose(1, 2, 0.5, 0, 0, 0.4); };
  const auto imu = simulate_imu(still, 0.0, 10.0, cfg);
  ASSERT_EQ(imu.size(), 2001u);
  Eigen::Vector3d acc = Eigen::Vector3d::Zero(), gyro = Eigen::Vector3d::Zero();
  for (const auto& s : imu) acc += s.accel_m_s2, gyro += s.gyro_rad_s;
  acc /= double(imu.size());
  gyro /= double(imu.size());
  // Mean = gravity + constant bias (bias sigma 0.05 m/s^2, 0.005 rad/s: 5 sigma bounds).
  EXPECT_NEAR(acc.z(), 9.80665, 0.25);
  EXPECT_NEAR(acc.head<2>().norm(), 0.0, 0.36);
  EXPECT_LT(gyro.norm(), 0.045);
  EXPECT_NEAR(imu[1].stamp_s - imu[0].stamp_s, 0.005, 1e-12);
  // Tilted by 30 deg of roll, gravity shows on y.
  const auto tilted = simulate_imu([](double) { return make_pose(0, 0, 0, 0.5236, 0, 0); }, 0, 1,
                                   ImuConfig{.gyro_noise_rad_s = 0,
                                             .accel_noise_m_s2 = 0,
                                             .gyro_bias_sigma_rad_s = 0,
                                             .accel_bias_sigma_m_s2 = 0});
  EXPECT_NEAR(tilted[10].accel_m_s2.y(), 9.80665 * std::sin(0.5236), 1e-6);
}

TEST(SimMotion, ImuOnAMovingRobotIntegratesToItsTrueYaw) {
  const Scene scene = make_greenhouse_scene({}, 3);
  const auto motion = drive_scene_route(scene, 40.0);
  ImuConfig cfg{.gyro_noise_rad_s = 0.003,
                .accel_noise_m_s2 = 0.03,
                .gyro_bias_sigma_rad_s = 0,
                .accel_bias_sigma_m_s2 = 0};
  const auto imu = simulate_imu(motion.base_pose_fn(), 0.0, 40.0, cfg);
  double yaw = yaw_of(motion.T_world_base(0.0));
  for (std::size_t i = 1; i < imu.size(); ++i)
    yaw += 0.5 * (imu[i - 1].gyro_rad_s.z() + imu[i].gyro_rad_s.z()) *
           (imu[i].stamp_s - imu[i - 1].stamp_s);
  const double truth = yaw_of(motion.T_world_base(40.0));
  EXPECT_NEAR(std::remainder(yaw - truth, 2 * std::numbers::pi), 0.0, 0.03);
  // The route has a U-turn into the next aisle within 40 s at 0.6 m/s (25 m aisles).
  const double moved =
      (motion.T_world_base(40.0).translation() - motion.T_world_base(0.0).translation()).norm();
  EXPECT_GT(moved, 2.0);
  // Forward acceleration at cruise is ~0; specific force on z ~ gravity.
  EXPECT_NEAR(imu[imu.size() / 4].accel_m_s2.z(), 9.80665, 0.3);
}

TEST(SimMotion, WheelOdometryDeadReckonsNearTheTruth) {
  const Scene scene = make_greenhouse_scene({}, 1);
  const auto motion = drive_scene_route(scene, 30.0);
  WheelOdometryConfig exact{.slip_sigma = 0, .noise_m_s = 0};
  const auto odo = simulate_wheel_odometry(motion.base_pose_fn(), 0.0, 30.0, exact);
  const Pose end = motion.T_world_base(30.0);
  const double dist = motion.base().path_length_m();
  ASSERT_GT(dist, 10.0);
  EXPECT_LT((odo.back().dead_reckoned.translation().head<2>() - end.translation().head<2>()).norm(),
            0.01 * dist);
  EXPECT_NEAR(odo.back().left_rad_s, odo.back().left_m_s / exact.wheel_radius_m, 1e-9);
  // With slip the dead-reckoning drifts, but stays on the order of the slip.
  const auto slipping = simulate_wheel_odometry(motion.base_pose_fn(), 0.0, 30.0,
                                                WheelOdometryConfig{.slip_sigma = 0.05});
  const double err =
      (slipping.back().dead_reckoned.translation().head<2>() - end.translation().head<2>()).norm();
  EXPECT_GT(err, 1e-4);
  EXPECT_LT(err, 0.15 * dist);
}

TEST(SimMotion, RobotDrivesTheRouteOnTheGround) {
  const Scene scene = make_terrain_scene({}, 5);
  const auto motion = drive_scene_route(scene, 20.0);
  ASSERT_GT(motion.base().size(), 3000u);  // 200 Hz
  for (double t = 0; t <= 20.0; t += 0.5) {
    const Pose T = motion.T_world_base(t);
    EXPECT_NEAR(T.translation().z(), scene.ground_height_at(T.translation().head<2>()), 0.1);
    EXPECT_NEAR(motion.T_world_lidar(t).translation().z() - T.translation().z(),
                scene.sensor_height_m(), 0.05);
  }
  // 1.5 m/s after the ramp-up.
  EXPECT_GT(motion.base().path_length_m(), 25.0);
}

TEST(SimMotion, TimedWaypointsAreReachedOnTime) {
  const Scene scene = make_lawn_scene({}, 0);
  const std::vector<TimedWaypoint> wps = {
      {0.0, {2, 2}}, {4.0, {6, 2}}, {6.0, {6, 2}}, {10.0, {6, 6}}};
  const auto motion = timed_route(scene, wps);
  EXPECT_NEAR(motion.start_s(), 0.0, 1e-12);
  EXPECT_NEAR(motion.end_s(), 10.0, 1e-12);
  for (const auto& w : wps) {
    EXPECT_LT((motion.T_world_base(w.stamp_s).translation().head<2>() - w.xy_m).norm(), 1e-9);
    EXPECT_NEAR(motion.T_world_base(w.stamp_s).translation().z(), scene.ground_height_at(w.xy_m),
                0.05);
  }
  EXPECT_LT((motion.T_world_base(2.0).translation().head<2>() - Eigen::Vector2d(4, 2)).norm(),
            1e-6);
  EXPECT_NEAR(yaw_of(motion.T_world_base(5.0)), 0.0, 1e-9);  // standing: keeps its heading
  EXPECT_NEAR(yaw_of(motion.T_world_base(8.0)), std::numbers::pi / 2, 1e-9);
  const std::vector<TimedWaypoint> bad = {{1.0, {0, 0}}, {1.0, {1, 0}}};
  EXPECT_THROW(timed_route(scene, bad), std::invalid_argument);
}

TEST(SimMotion, MowerFollowsTheOperatorAtTheLag) {
  LawnConfig cfg;
  cfg.operator_stops = true;
  cfg.stop_time_s = 15.0;
  cfg.stop_duration_s = 6.0;
  const Scene scene = make_lawn_scene(cfg, 2);
  DriveConfig drive;
  drive.follow_lag_m = 2.5;
  const auto motion = follow_operator(scene, 1, 30.0, drive);
  for (double t : {10.0, 20.0, 27.0}) {
    const auto op = scene.people_at(t)[0];
    const double gap = (motion.T_world_base(t).translation().head<2>() - op.position_m).norm();
    EXPECT_GT(gap, 1.2) << "t = " << t;
    EXPECT_LT(gap, 4.0) << "t = " << t;
  }
  // While the operator stands, the mower comes to rest too.
  const double moved =
      (motion.T_world_base(20.5).translation() - motion.T_world_base(19.0).translation()).norm();
  EXPECT_LT(moved, 0.05);
  EXPECT_THROW(follow_operator(scene, 9, 5.0), std::invalid_argument);
}

}  // namespace
}  // namespace fieldlidar::sim
