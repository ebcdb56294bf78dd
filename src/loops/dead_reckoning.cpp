// Wheel odometry with a gyro as the closed loop's pose source (pose_source.hpp): the simulated
// wheel and IMU streams of each control period integrated.

#include <algorithm>
#include <cmath>

#include "fieldlidar/loops/pose_source.hpp"

namespace fieldlidar::loops {

DeadReckoningPoseSource::DeadReckoningPoseSource(const MotionStreamsConfig& streams)
    : streams_(streams) {}

follow::Pose2 DeadReckoningPoseSource::advance(const std::function<Pose(double)>& T_world_base,
                                               double t0_s, double t1_s) {
  const auto period = streams_.next(T_world_base, t0_s, t1_s);
  const auto& gyro = period.imu;
  const auto& wheel = period.wheels;
  const auto& wheels = streams_.config().wheels;
  const auto& imu = streams_.config().imu;
  // A period the wheels stand still in (speeds within 4 sigma of their noise) teaches the
  // gyro's bias: it reads the bias alone.
  const double still_m_s = 4 * wheels.noise_m_s;
  const bool still = std::all_of(wheel.begin(), wheel.end(), [&](const auto& w) {
    return std::abs(w.left_m_s) <= still_m_s && std::abs(w.right_m_s) <= still_m_s;
  });
  if (still)
    for (const auto& s : gyro) {
      still_gyro_sum_ += s.gyro_rad_s.z();
      ++still_samples_;
    }
  const double bias = still_samples_ ? still_gyro_sum_ / double(still_samples_) : 0.0;
  auto rate = [&](std::size_t g) { return gyro[g].gyro_rad_s.z() - bias; };
  // Forward speed from the wheels, yaw rate from the gyro, each held over its sample period.
  const double dt_wheel = 1.0 / wheels.rate_hz, dt_gyro = 1.0 / imu.rate_hz;
  std::size_t g = 0;
  double yaw = pose_.yaw_rad;
  for (const auto& w : wheel) {
    const double until = w.stamp_s + dt_wheel;
    for (; g < gyro.size() && gyro[g].stamp_s < until; ++g) yaw += rate(g) * dt_gyro;
    const double mid = 0.5 * (pose_.yaw_rad + yaw);
    pose_.x_m += w.linear_m_s * dt_wheel * std::cos(mid);
    pose_.y_m += w.linear_m_s * dt_wheel * std::sin(mid);
    pose_.yaw_rad = yaw;
  }
  for (; g < gyro.size(); ++g) yaw += rate(g) * dt_gyro;
  pose_.yaw_rad = std::remainder(yaw, 2 * M_PI);
  return pose_;
}

}  // namespace fieldlidar::loops
