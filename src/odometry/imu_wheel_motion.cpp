// seed 002, step a: the lidar pose at each time of a sweep from the IMU gyro (rotation), the wheel
// speed (translation) or, without wheels, the accelerometer carrying the last velocity on.

#include <algorithm>
#include <cmath>

#include "fieldlidar/core/pose.hpp"
#include "fieldlidar/odometry/deskew.hpp"

namespace fieldlidar::odometry {

namespace {

/// True when the samples cover [t0, t1] with no gap wider than max_gap_s.
template <class S>
bool covers(std::span<const S> s, double t0, double t1, double max_gap_s) {
  if (s.empty() || s.front().stamp_s > t0 + max_gap_s || s.back().stamp_s < t1 - max_gap_s)
    return false;
  for (std::size_t i = 1; i < s.size(); ++i)
    if (s[i].stamp_s > t0 && s[i - 1].stamp_s < t1 && s[i].stamp_s - s[i - 1].stamp_s > max_gap_s)
      return false;
  return true;
}

/// Value of the sample stream at time t (the last sample at or before t, else the first).
template <class S>
const S& sample_at(std::span<const S> s, double t) {
  auto it =
      std::upper_bound(s.begin(), s.end(), t, [](double v, const S& x) { return v < x.stamp_s; });
  return it == s.begin() ? *it : *(it - 1);
}

}  // namespace

std::optional<ImuWheelMotion> integrate_motion(std::span<const ImuSample> imu,
                                               std::span<const WheelSample> wheels, double t0_s,
                                               double t1_s, const Eigen::Vector3d& v0_lidar_m_s,
                                               const Eigen::Vector3d& g_base0_m_s2,
                                               const DeskewConfig& config) {
  const bool has_imu = config.use_imu && covers(imu, t0_s, t1_s, config.max_imu_gap_s);
  const bool has_wheels = config.use_wheels && covers(wheels, t0_s, t1_s, config.max_wheel_gap_s);
  if (!has_imu && !has_wheels) return std::nullopt;

  const Pose& T_bl = config.T_base_lidar;
  const Pose T_lb = T_bl.inverse();
  // Integrate the base pose in the base frame at t0 on a fixed step.
  constexpr double kStep = 0.005;
  const int steps = std::max(1, int(std::ceil((t1_s - t0_s) / kStep)));
  const double dt = (t1_s - t0_s) / steps;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  Eigen::Vector3d v = T_bl.linear() * v0_lidar_m_s;  // base frame at t0 (lever arm ignored)
  ImuWheelMotion out;
  out.source = has_imu && has_wheels ? MotionSource::kImuWheels
               : has_imu             ? MotionSource::kImu
                                     : MotionSource::kWheels;
  out.motion.push_back(0.0, Pose::Identity());
  for (int k = 0; k < steps; ++k) {
    const double t = t0_s + (k + 0.5) * dt;
    Eigen::Vector3d w = Eigen::Vector3d::Zero();
    if (has_imu) {
      w = sample_at(imu, t).gyro_rad_s;
    } else {
      w.z() = sample_at(wheels, t).yaw_rate_rad_s;
    }
    const Eigen::Matrix3d R_mid = R * exp_so3(0.5 * dt * w);
    if (has_wheels) {
      v = R_mid * Eigen::Vector3d(sample_at(wheels, t).linear_m_s, 0, 0);
    } else {
      const Eigen::Vector3d a = R_mid * sample_at(imu, t).accel_m_s2 - g_base0_m_s2;
      v += a * dt;
    }
    p += v * dt;
    R = R * exp_so3(dt * w);
    Pose T_b0_bt = Pose::Identity();
    T_b0_bt.linear() = R;
    T_b0_bt.translation() = p;
    out.motion.push_back((k + 1) * dt, T_lb * T_b0_bt * T_bl);
  }
  return out;
}

}  // namespace fieldlidar::odometry
