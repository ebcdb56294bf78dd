#pragma once
// Test helpers: simulated sequences and trajectory errors (ATE after a rigid Umeyama alignment,
// RPE per frame, drift over segments) computed here, independent of the code under test.

#include <cmath>
#include <cstdlib>
#include <vector>

#include <Eigen/Geometry>

#include "fieldlidar/core/pose.hpp"
#include "fieldlidar/odometry/lidar_odometry.hpp"
#include "fieldlidar/sim/lidar_simulator.hpp"
#include "fieldlidar/sim/motion.hpp"
#include "fieldlidar/sim/scenes.hpp"

namespace fieldlidar::odometry::test {

struct SimSequence {
  SensorModel sensor;
  std::vector<PointCloud> frames;
  std::vector<Pose> truth;  ///< T_world_lidar at each sweep start
  std::vector<ImuSample> imu;
  std::vector<WheelSample> wheels;
  Pose T_base_lidar = Pose::Identity();
};

/// `frames` sweeps of the scene's route from t = first * period, noise seed `seed`.
inline SimSequence simulate_sequence(sim::SceneKind kind, int first, int frames,
                                     std::uint64_t seed = 0,
                                     SensorModel sensor = SensorModel::vlp16()) {
  SimSequence s;
  s.sensor = sensor;
  const sim::Scene scene = sim::make_scene(kind, 0);
  const double period = sensor.sweep_period_s();
  const double t_end = (first + frames) * period + 1.0;
  const auto motion = sim::drive_scene_route(scene, t_end);
  s.T_base_lidar = motion.T_base_lidar();
  sim::SimConfig cfg;
  cfg.seed = seed + 1;
  const sim::LidarSimulator simulator(scene, sensor, cfg);
  for (int i = first; i < first + frames; ++i) {
    auto f = simulator.scan(i * period, motion.lidar_pose_fn());
    f.cloud.stamp_s = f.stamp_s;
    s.frames.push_back(std::move(f.cloud));
    s.truth.push_back(f.T_world_lidar_start);
  }
  const double t0 = first * period, t1 = (first + frames) * period;
  for (const auto& m : sim::simulate_imu(motion.base_pose_fn(), t0, t1, {.seed = 7 + seed}))
    s.imu.push_back({m.stamp_s, m.gyro_rad_s, m.accel_m_s2});
  for (const auto& m :
       sim::simulate_wheel_odometry(motion.base_pose_fn(), t0, t1, {.seed = 11 + seed}))
    s.wheels.push_back({m.stamp_s, m.linear_m_s, m.yaw_rate_rad_s});
  return s;
}

struct TrajectoryErrors {
  double ate_m = 0;      ///< RMSE after rigid alignment
  double rpe_t_m = 0;    ///< RMS per-frame translation error
  double rpe_r_deg = 0;  ///< RMS per-frame rotation error
  double drift_pct = 0;  ///< mean translation error / length over segments
  double path_m = 0;
};

inline double angle_deg(const Eigen::Matrix3d& R) {
  return Eigen::AngleAxisd(R).angle() * 180.0 / 3.14159265358979;
}

/// est and ref: poses of the same frames; segments of `segment_m` for the drift.
inline TrajectoryErrors trajectory_errors(const std::vector<Pose>& est,
                                          const std::vector<Pose>& ref, double segment_m,
                                          bool with_scale = false) {
  TrajectoryErrors e;
  const std::size_t n = std::min(est.size(), ref.size());
  Eigen::Matrix3Xd A(3, n), B(3, n);
  for (std::size_t i = 0; i < n; ++i) {
    A.col(i) = est[i].translation();
    B.col(i) = ref[i].translation();
  }
  const Eigen::Matrix4d T = Eigen::umeyama(A, B, with_scale);
  double se = 0;
  for (std::size_t i = 0; i < n; ++i)
    se +=
        ((T.topLeftCorner<3, 3>() * A.col(i) + T.topRightCorner<3, 1>()) - B.col(i)).squaredNorm();
  e.ate_m = std::sqrt(se / n);
  double st = 0, sr = 0;
  std::vector<double> dist(n, 0.0);
  for (std::size_t i = 1; i < n; ++i) {
    const Pose de = est[i - 1].inverse() * est[i], dr = ref[i - 1].inverse() * ref[i];
    const Pose err = dr.inverse() * de;
    st += err.translation().squaredNorm();
    sr += std::pow(angle_deg(err.linear()), 2);
    dist[i] = dist[i - 1] + dr.translation().norm();
  }
  e.rpe_t_m = n > 1 ? std::sqrt(st / (n - 1)) : 0;
  e.rpe_r_deg = n > 1 ? std::sqrt(sr / (n - 1)) : 0;
  e.path_m = dist.back();
  double sum = 0;
  int count = 0;
  for (std::size_t i = 0; i < n; ++i) {
    std::size_t j = i;
    while (j < n && dist[j] - dist[i] < segment_m) ++j;
    if (j >= n) break;
    const Pose de = est[i].inverse() * est[j], dr = ref[i].inverse() * ref[j];
    sum += (dr.inverse() * de).translation().norm() / (dist[j] - dist[i]);
    ++count;
  }
  e.drift_pct = count ? 100.0 * sum / count : 0.0;
  return e;
}

/// Runs the odometry over a simulated sequence; poses relative to the first truth pose.
inline std::vector<Pose> run(const SimSequence& s, OdometryConfig cfg, bool motion_streams,
                             std::vector<OdometryResult>* results = nullptr) {
  cfg.deskew.T_base_lidar = s.T_base_lidar;
  LidarOdometry odo(s.sensor, cfg);
  if (motion_streams) {
    odo.add_imu(s.imu);
    odo.add_wheels(s.wheels);
  }
  std::vector<Pose> est;
  for (const auto& f : s.frames) {
    auto r = odo.register_frame(f);
    est.push_back(r.T_world_lidar);
    if (results) results->push_back(std::move(r));
  }
  return est;
}

/// Tuning knobs of the report runs, from the environment.
inline void apply_env(OdometryConfig& c) {
  auto num = [](const char* name, double& v) {
    if (const char* s = std::getenv(name)) v = std::atof(s);
  };
  auto integer = [](const char* name, int& v) {
    if (const char* s = std::getenv(name)) v = std::atoi(s);
  };
  num("THICK", c.map.max_plane_thickness_m);
  integer("VOXPTS", c.map.max_points_per_voxel);
  num("VOXM", c.map.voxel_m);
  num("SPACING", c.map.min_point_spacing_m);
  integer("LMIT", c.lm.max_iterations);
  integer("ROUNDS", c.max_associations);
  num("CONV", c.convergence_m);
  num("REASSOC", c.reassociate_m);
  num("COARSE", c.coarse_voxel_m);
  num("COARSEFRAC", c.coarse_below_fraction);
  num("SPREAD", c.map.min_plane_spread);
  num("CURV", c.features.curvature_threshold);
  integer("NEDGE", c.features.edges_per_sector);
  integer("NPLANE", c.features.planes_per_sector);
  integer("STRIDE", c.features.map_plane_stride);
  num("ROBUST", c.lm.robust_scale_m);
  num("DEGEN", c.lm.degenerate_eigenvalue);
  if (std::getenv("HOLDDEGEN")) c.lm.hold_degenerate = true;
  if (std::getenv("NODESKEW")) c.deskew.enabled = false;
  if (std::getenv("CVDESKEW")) c.deskew.constant_velocity = true;
  if (std::getenv("GROUND")) c.preprocess.split_ground = true;
  if (std::getenv("CLUSTERS")) c.preprocess.drop_small_clusters = true;
  if (std::getenv("ROBUSTGROUND")) c.preprocess.ground.method = segmentation::GroundMethod::kRobust;
}

inline std::vector<Pose> relative_to_first(const std::vector<Pose>& poses) {
  std::vector<Pose> out;
  for (const auto& p : poses) out.push_back(poses.front().inverse() * p);
  return out;
}

}  // namespace fieldlidar::odometry::test
