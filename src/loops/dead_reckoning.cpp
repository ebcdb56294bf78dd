// Wheel odometry with an IMU as the closed loop's pose source (pose_source.hpp): the simulated
// wheel and IMU streams of each control period integrated, the attitude from the gyro's three
// axes.

#include <algorithm>
#include <cmath>

#include "fieldlidar/loops/pose_source.hpp"

namespace fieldlidar::loops {

namespace {

/// `attitude` with the roll and pitch that make `specific_force` (the accelerometer's mean at
/// rest, gravity alone, base frame) point up, its yaw kept.
Pose levelled(const Pose& attitude, const Eigen::Vector3d& specific_force) {
  const double roll = std::atan2(specific_force.y(), specific_force.z());
  const double pitch =
      std::atan2(-specific_force.x(), std::hypot(specific_force.y(), specific_force.z()));
  return make_pose(0, 0, 0, roll, pitch, yaw_of(attitude));
}

}  // namespace

DeadReckoningPoseSource::DeadReckoningPoseSource(const MotionStreamsConfig& streams)
    : streams_(streams) {}

follow::Pose2 DeadReckoningPoseSource::advance(const std::function<Pose(double)>& T_world_base,
                                               double t0_s, double t1_s) {
  const auto period = streams_.next(T_world_base, t0_s, t1_s);
  const auto& imu_samples = period.imu;
  const auto& wheel = period.wheels;
  const auto& wheels = streams_.config().wheels;
  const auto& imu = streams_.config().imu;
  // A period the wheels stand still in (speeds within 4 sigma of their noise) teaches the
  // gyro's bias (it reads the bias alone) and levels the attitude (the accelerometer reads
  // gravity alone). The first period levels it whatever the wheels do.
  const double still_m_s = 4 * wheels.noise_m_s;
  const bool still = std::all_of(wheel.begin(), wheel.end(), [&](const auto& w) {
    return std::abs(w.left_m_s) <= still_m_s && std::abs(w.right_m_s) <= still_m_s;
  });
  if ((still || !levelled_) && !imu_samples.empty()) {
    Eigen::Vector3d force = Eigen::Vector3d::Zero();
    for (const auto& s : imu_samples) force += s.accel_m_s2;
    if (force.norm() > 0) {
      attitude_ = levelled(attitude_, force);
      levelled_ = true;
    }
  }
  if (still)
    for (const auto& s : imu_samples) {
      still_gyro_sum_ += s.gyro_rad_s;
      ++still_samples_;
    }
  const Eigen::Vector3d bias = still_samples_
                                   ? Eigen::Vector3d(still_gyro_sum_ / double(still_samples_))
                                   : Eigen::Vector3d::Zero();
  // Forward speed from the wheels along the base's x axis, the attitude from the gyro, each
  // held over its sample period.
  const double dt_wheel = 1.0 / wheels.rate_hz, dt_gyro = 1.0 / imu.rate_hz;
  std::size_t g = 0;
  for (const auto& w : wheel) {
    const double until = w.stamp_s + dt_wheel;
    const Eigen::Vector3d forward_before = attitude_.linear().col(0);
    for (; g < imu_samples.size() && imu_samples[g].stamp_s < until; ++g)
      attitude_.linear() =
          attitude_.linear() * exp_so3((imu_samples[g].gyro_rad_s - bias) * dt_gyro);
    const Eigen::Vector3d forward = 0.5 * (forward_before + attitude_.linear().col(0));
    pose_.x_m += w.linear_m_s * dt_wheel * forward.x();
    pose_.y_m += w.linear_m_s * dt_wheel * forward.y();
  }
  for (; g < imu_samples.size(); ++g)
    attitude_.linear() = attitude_.linear() * exp_so3((imu_samples[g].gyro_rad_s - bias) * dt_gyro);
  pose_.yaw_rad = yaw_of(attitude_);
  return pose_;
}

}  // namespace fieldlidar::loops
