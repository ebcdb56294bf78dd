// The closed loop's pose source: LiDAR odometry fed with each simulated sweep and the IMU and
// wheel samples of the control period, converted from the simulator's streams.

#include "fieldlidar/loops/pose_source.hpp"

#include <random>
#include <vector>

namespace fieldlidar::loops {

std::string to_string(PoseSource s) {
  return s == PoseSource::kTruth ? "truth" : "odometry";
}

std::optional<PoseSource> pose_source_from_string(const std::string& name) {
  for (auto s : {PoseSource::kOdometry, PoseSource::kTruth})
    if (to_string(s) == name) return s;
  return std::nullopt;
}

follow::Pose2 MowerSegment::at(double t_s) const {
  return follow::predict_pose(start, v_m_s, dv_m_s, track_width_m, t_s - t0_s);
}

SimulatedStreams::SimulatedStreams(const MotionStreamsConfig& config) : config_(config) {
  std::mt19937_64 rng(config.imu.seed);
  std::normal_distribution<double> n01(0.0, 1.0);
  for (int i = 0; i < 3; ++i) gyro_bias_rad_s_[i] = config.imu.gyro_bias_sigma_rad_s * n01(rng);
  for (int i = 0; i < 3; ++i) accel_bias_m_s2_[i] = config.imu.accel_bias_sigma_m_s2 * n01(rng);
}

SimulatedStreams::Period SimulatedStreams::next(const std::function<Pose(double)>& T_world_base,
                                                double t0_s, double t1_s) {
  const std::uint64_t k = ++periods_;
  sim::ImuConfig imu = config_.imu;
  imu.gyro_bias_sigma_rad_s = 0;
  imu.accel_bias_sigma_m_s2 = 0;
  imu.seed = config_.imu.seed + 0x9E3779B97F4A7C15ull * k;
  sim::WheelOdometryConfig wheels = config_.wheels;
  wheels.seed = config_.wheels.seed + 0x9E3779B97F4A7C15ull * k;
  Period p;
  p.imu = sim::simulate_imu(T_world_base, t0_s, t1_s - 0.5 / imu.rate_hz, imu);
  for (auto& s : p.imu) {
    s.gyro_rad_s += gyro_bias_rad_s_;
    s.accel_m_s2 += accel_bias_m_s2_;
  }
  p.wheels = sim::simulate_wheel_odometry(T_world_base, t0_s, t1_s - 0.5 / wheels.rate_hz, wheels);
  return p;
}

OdometryPoseSource::OdometryPoseSource(const SensorModel& sensor, double sensor_height_m,
                                       odometry::OdometryConfig config,
                                       const MotionStreamsConfig& streams)
    : odometry_(sensor,
                [&] {
                  config.deskew.T_base_lidar = make_pose(0, 0, sensor_height_m, 0, 0, 0);
                  config.expected_period_s = sensor.sweep_period_s();
                  return config;
                }()),
      streams_(streams) {}

void OdometryPoseSource::add_streams(const std::function<Pose(double)>& T_world_base, double t0_s,
                                     double t1_s) {
  const auto period = streams_.next(T_world_base, t0_s, t1_s);
  std::vector<odometry::ImuSample> imu_out;
  imu_out.reserve(period.imu.size());
  for (const auto& s : period.imu) imu_out.push_back({s.stamp_s, s.gyro_rad_s, s.accel_m_s2});
  std::vector<odometry::WheelSample> wheel_out;
  wheel_out.reserve(period.wheels.size());
  for (const auto& s : period.wheels)
    wheel_out.push_back({s.stamp_s, s.linear_m_s, s.yaw_rate_rad_s});
  odometry_.add_imu(imu_out);
  odometry_.add_wheels(wheel_out);
}

odometry::OdometryResult OdometryPoseSource::register_sweep(const PointCloud& sweep) {
  return odometry_.register_frame(sweep);
}

}  // namespace fieldlidar::loops
