#pragma once
// Test helpers: simulated sequences, and their trajectory errors by the core metrics (ATE after a
// rigid Umeyama alignment, RPE per frame, drift over segments), which have tests of their own.

#include <cmath>
#include <cstdlib>
#include <functional>
#include <vector>

#include <Eigen/Geometry>

#include "fieldlidar/core/pose.hpp"
#include "fieldlidar/core/trajectory_metrics.hpp"
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
  if (const char* v = std::getenv("FIELDLIDAR_SIM_RANGE_NOISE")) cfg.range_noise_m = std::atof(v);
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

/// A handheld-like sweep: from the start of the scene's route the sensor walks forward at
/// `speed_m_s` while its yaw swings by +-amplitude_deg with period_s; one sweep every
/// `frame_step` sweep periods (a 2 Hz recording: 5), an IMU on the sensor, no wheels.
inline SimSequence simulate_yaw_sweep(sim::SceneKind kind, int frames, int frame_step,
                                      double amplitude_deg, double period_s, double speed_m_s,
                                      SensorModel sensor = SensorModel::vlp16()) {
  SimSequence s;
  s.sensor = sensor;
  const sim::Scene scene = sim::make_scene(kind, 0);
  const Pose start = sim::drive_scene_route(scene, 1.0).T_world_lidar(0.0);
  const double amplitude = amplitude_deg * 3.14159265358979 / 180;
  const std::function<Pose(double)> pose = [=](double t) {
    return start * make_pose(speed_m_s * t, 0, 0, 0, 0,
                             amplitude * std::sin(2 * 3.14159265358979 * t / period_s));
  };
  sim::SimConfig cfg;
  cfg.seed = 1;
  const sim::LidarSimulator simulator(scene, sensor, cfg);
  const double dt = frame_step * sensor.sweep_period_s();
  for (int i = 0; i < frames; ++i) {
    auto f = simulator.scan(i * dt, pose);
    f.cloud.stamp_s = f.stamp_s;
    s.frames.push_back(std::move(f.cloud));
    s.truth.push_back(f.T_world_lidar_start);
  }
  for (const auto& m : sim::simulate_imu(pose, 0.0, frames * dt, {.seed = 7}))
    s.imu.push_back({m.stamp_s, m.gyro_rad_s, m.accel_m_s2});
  return s;
}

struct TrajectoryErrors {
  double ate_m = 0;       ///< RMSE after rigid alignment
  double rpe_t_m = 0;     ///< RMS per-frame translation error
  double rpe_r_deg = 0;   ///< RMS per-frame rotation error
  double drift_pct = 0;   ///< mean translation error / length over segments
  double path_m = 0;      ///< reference path length
  double est_path_m = 0;  ///< estimated path length
  double ate_se3_m = 0;   ///< ATE RMSE after a rigid alignment
  double ate_sim3_m = 0;  ///< ATE RMSE after a similarity alignment
  double scale = 1;       ///< reference / estimate of the similarity alignment
};

inline double angle_deg(const Eigen::Matrix3d& R) {
  return rotation_angle_rad(R) * 180.0 / 3.14159265358979;
}

/// est and ref: poses of the same frames, scored by the core metrics (evaluate_trajectory):
/// ATE after a rigid (or similarity) alignment, RMS RPE per frame, the KITTI drift over
/// sub-sequences of `segment_m` starting at every frame.
inline TrajectoryErrors trajectory_errors(const std::vector<Pose>& est,
                                          const std::vector<Pose>& ref, double segment_m,
                                          bool with_scale = false) {
  const std::size_t n = std::min(est.size(), ref.size());
  const std::vector<Pose> e(est.begin(), est.begin() + long(n)),
      r(ref.begin(), ref.begin() + long(n));
  TrajectoryMetricsConfig config;
  config.segment_lengths_m = {segment_m};
  config.segment_step_frames = 1;
  const TrajectoryMetrics m = evaluate_trajectory(e, r, config);
  TrajectoryErrors out;
  out.ate_m = (with_scale ? m.ate_sim3 : m.ate_se3).translation_m.rmse;
  out.rpe_t_m = m.rpe.translation_m.rmse;
  out.rpe_r_deg = m.rpe.rotation_deg.rmse;
  out.drift_pct = m.drift.translation_pct;
  out.path_m = m.reference_path_m;
  out.est_path_m = m.estimate_path_m;
  out.ate_se3_m = m.ate_se3.translation_m.rmse;
  out.ate_sim3_m = m.ate_sim3.translation_m.rmse;
  out.scale = m.ate_sim3.alignment.scale;
  return out;
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
  num("COARSEGAIN", c.coarse_min_gain);
  num("COARSETYP", c.coarse_below_typical);
  num("SPREAD", c.map.min_plane_spread);
  num("CURV", c.features.curvature_threshold);
  integer("NEDGE", c.features.edges_per_sector);
  integer("NPLANE", c.features.planes_per_sector);
  integer("STRIDE", c.features.map_plane_stride);
  num("PLANETHIN", c.features.match_plane_spacing_m);
  num("EDGETHIN", c.features.match_edge_spacing_m);
  num("ROBUST", c.lm.robust_scale_m);
  num("DEGEN", c.lm.degenerate_ratio);
  integer("NEIGH", c.map.neighbours);
  num("NEIGHDIST", c.map.max_neighbour_distance_m);
  num("PLANEDIST", c.map.max_plane_distance_m);
  num("AZPERIOD", c.deskew.azimuth_time_period_s);
  num("AZSTART", c.deskew.azimuth_start_deg);
  if (std::getenv("AZCCW")) c.deskew.azimuth_clockwise = false;
  num("ELEV", c.preprocess.elevation_correction_deg);
  num("MINR", c.features.min_range_m);
  num("MAXR", c.features.max_range_m);
  num("MAPR", c.map.max_range_m);
  num("OCCL", c.features.occlusion_ratio);
  integer("FNEIGH", c.features.neighbours);
  integer("SECTORS", c.features.sectors);
  if (std::getenv("HOLDDEGEN")) c.lm.hold_degenerate = true;
  if (std::getenv("NODESKEW")) c.deskew.enabled = false;
  if (std::getenv("CVDESKEW")) c.deskew.constant_velocity = true;
  if (std::getenv("NOMID")) c.deskew.mid_sweep_reference = false;
  if (std::getenv("LASTVEL")) c.deskew.velocity_from_two_sweeps = false;
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
