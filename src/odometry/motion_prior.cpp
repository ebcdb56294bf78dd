// seed 002, step a: the pose prior of a sweep and its motion during the sweep, from the IMU and
// wheel streams when they cover it, else from the last sweep-to-sweep motion.

#include <algorithm>
#include <cmath>

#include <fmt/core.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/odometry/lidar_odometry.hpp"

namespace fieldlidar::odometry {

namespace {

/// The motion `delta` scaled by s along its geodesic (s may exceed 1).
Pose scale_motion(const Pose& delta, double s) {
  const Eigen::AngleAxisd aa(delta.linear());
  Pose out = Pose::Identity();
  out.linear() = Eigen::AngleAxisd(aa.angle() * s, aa.axis()).toRotationMatrix();
  out.translation() = delta.translation() * s;
  return out;
}

bool finite(const ImuSample& s) {
  return std::isfinite(s.stamp_s) && s.gyro_rad_s.allFinite() && s.accel_m_s2.allFinite();
}
bool finite(const WheelSample& s) {
  return std::isfinite(s.stamp_s) && std::isfinite(s.linear_m_s) && std::isfinite(s.yaw_rate_rad_s);
}

/// One NaN sample would be integrated into every later pose: refused whole, before any is kept.
template <class S>
void check_finite(std::span<const S> samples, const char* what) {
  for (std::size_t i = 0; i < samples.size(); ++i)
    if (!finite(samples[i]))
      throw Error(
          fmt::format("{} sample {} (stamp {} s) holds NaN or inf", what, i, samples[i].stamp_s));
}

template <class S>
void append_in_order(std::vector<S>& dst, std::span<const S> src) {
  for (const auto& s : src)
    if (dst.empty() || s.stamp_s > dst.back().stamp_s) dst.push_back(s);
}

}  // namespace

void LidarOdometry::add_imu(std::span<const ImuSample> samples) {
  check_finite(samples, "IMU");
  append_in_order(imu_, samples);
  streams_given_ = streams_given_ || !samples.empty();
}
void LidarOdometry::add_wheels(std::span<const WheelSample> samples) {
  check_finite(samples, "wheel");
  append_in_order(wheels_, samples);
  streams_given_ = streams_given_ || !samples.empty();
}

void LidarOdometry::trim_streams(double before_s) {
  auto drop = [before_s](auto& v) {
    auto it =
        std::find_if(v.begin(), v.end(), [&](const auto& s) { return s.stamp_s >= before_s; });
    v.erase(v.begin(), it);
  };
  drop(imu_);
  drop(wheels_);
}

LidarOdometry::Prior LidarOdometry::predict(double stamp_s, std::vector<std::string>& warnings) {
  Prior prior{T_world_lidar_, {}, MotionSource::kConstantVelocity};
  const double period = sensor_.sweep_period_s();
  const Pose T_wb = T_world_lidar_ * config_.deskew.T_base_lidar.inverse();
  if (!initialised_ && !imu_.empty()) {
    // Gravity in the world frame from the accelerometer around the first sweep (robot at rest
    // or moving slowly).
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    int n = 0;
    for (const auto& s : imu_)
      if (s.stamp_s <= stamp_s + period) mean += s.accel_m_s2, ++n;
    if (n > 0) gravity_world_m_s2_ = T_wb.linear() * (mean / n);
  }
  const Eigen::Vector3d g_base = T_wb.linear().transpose() * gravity_world_m_s2_;
  const double last_period = last_period_s_ > 0 ? last_period_s_ : config_.expected_period_s;
  const Eigen::Vector3d v_lidar = T_last_delta_.translation() / last_period;
  double dt = stamp_s - last_stamp_s_;
  if (initialised_) {
    if (dt <= 0) {
      warnings.push_back(
          fmt::format("frame at {:.3f} s not after the previous one ({:.3f} s): "
                      "out of order, predicted as one period",
                      stamp_s, last_stamp_s_));
      dt = config_.expected_period_s;
    } else if (dt > 2.5 * config_.expected_period_s) {
      warnings.push_back(
          fmt::format("{:.3f} s gap in time before the frame at {:.3f} s", dt, stamp_s));
    }
    const auto between = dt > 0 && stamp_s > last_stamp_s_
                             ? integrate_motion(imu_, wheels_, last_stamp_s_, stamp_s, v_lidar,
                                                g_base, config_.deskew)
                             : std::nullopt;
    if (between) {
      prior.T_world_lidar = T_world_lidar_ * between->motion.last();
      prior.source = between->source;
    } else {
      prior.T_world_lidar = T_world_lidar_ * scale_motion(T_last_delta_, dt / last_period);
      if (!imu_.empty() || !wheels_.empty())
        warnings.push_back(
            fmt::format("IMU/wheel streams do not cover {:.3f}-{:.3f} s: constant-velocity prior",
                        last_stamp_s_, stamp_s));
    }
  }
  const Eigen::Vector3d g_now =
      (prior.T_world_lidar * config_.deskew.T_base_lidar.inverse()).linear().transpose() *
      gravity_world_m_s2_;
  if (auto sweep = integrate_motion(imu_, wheels_, stamp_s, stamp_s + period, v_lidar, g_now,
                                    config_.deskew)) {
    prior.sweep = std::move(sweep->motion);
    if (!initialised_) prior.source = sweep->source;
  } else if (config_.deskew.constant_velocity && !streams_given_ &&
             last_period <= config_.deskew.constant_velocity_max_period_factor * period) {
    // Only from consecutive sweeps: a velocity averaged over a longer gap (frames dropped, a
    // 2 Hz recording) says little about the motion within this sweep.
    Pose over_sweep = scale_motion(T_last_delta_, period / last_period);
    const double max_period = config_.deskew.constant_velocity_max_period_factor * period;
    if (config_.deskew.velocity_from_two_sweeps && prev_period_s_ > 0 &&
        prev_period_s_ <= max_period)
      over_sweep =
          interpolate(scale_motion(T_prev_delta_, period / prev_period_s_), over_sweep, 0.5);
    prior.sweep = SweepMotion::constant_velocity(over_sweep, period);
    prior.sweep_from_velocity = true;
  }
  return prior;
}

}  // namespace fieldlidar::odometry
