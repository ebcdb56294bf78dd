// seed 002, step a: the lidar's motion during a sweep and the sweep re-projected to its start.

#include "fieldlidar/odometry/deskew.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace fieldlidar::odometry {

SweepMotion SweepMotion::constant_velocity(const Pose& T_start_next, double period_s) {
  SweepMotion m;
  constexpr int kSamples = 8;
  for (int i = 0; i <= kSamples; ++i) {
    const double s = double(i) / kSamples;
    m.push_back(s * period_s, interpolate(Pose::Identity(), T_start_next, s));
  }
  return m;
}

void SweepMotion::push_back(double t_s, const Pose& T_start_t) {
  times_.push_back(t_s);
  poses_.push_back(T_start_t);
}

Pose SweepMotion::at(double t_s) const {
  if (poses_.empty()) return Pose::Identity();
  if (t_s <= times_.front()) return poses_.front();
  if (t_s >= times_.back()) return poses_.back();
  const auto it = std::upper_bound(times_.begin(), times_.end(), t_s);
  const std::size_t i = std::size_t(it - times_.begin());
  const double span = times_[i] - times_[i - 1];
  const double s = span > 0 ? (t_s - times_[i - 1]) / span : 0.0;
  return interpolate(poses_[i - 1], poses_[i], s);
}

std::vector<float> point_times(const PointCloud& cloud, const DeskewConfig& config) {
  std::vector<float> t(cloud.size(), 0.f);
  if (cloud.fields.time) {
    for (std::size_t i = 0; i < cloud.size(); ++i) t[i] = cloud.points[i].time;
  } else if (config.azimuth_time_period_s > 0) {
    // From the start azimuth in the sense of rotation: clockwise from behind (the default),
    // azimuth +pi at t = 0, 0 at half the period, -pi at the end.
    const double period = config.azimuth_time_period_s;
    const double start = config.azimuth_start_deg * std::numbers::pi / 180;
    const double two_pi = 2 * std::numbers::pi;
    for (std::size_t i = 0; i < cloud.size(); ++i) {
      const auto& p = cloud.points[i];
      const double az = std::atan2(double(p.y), double(p.x));
      double d = std::fmod(config.azimuth_clockwise ? start - az : az - start, two_pi);
      if (d < 0) d += two_pi;
      t[i] = float(d / two_pi * period);
    }
  }
  return t;
}

PointCloud deskew(const PointCloud& cloud, std::span<const float> times_s,
                  const SweepMotion& motion, double reference_s) {
  if (motion.empty()) return cloud;
  // Poses at a few fixed time steps, linear between them: the motion within a sweep is smooth.
  constexpr int kSteps = 32;
  const double t_end = std::max(motion.last_time_s(), 1e-6);
  const Pose T_ref_start = motion.at(reference_s).inverse();
  std::vector<Eigen::Matrix<float, 3, 4>> table(kSteps + 1);
  for (int k = 0; k <= kSteps; ++k)
    table[k] = (T_ref_start * motion.at(t_end * k / kSteps)).matrix().topRows<3>().cast<float>();
  PointCloud out = cloud;
  const std::size_t n = out.size();
  for (std::size_t i = 0; i < n;) {
    // A spinning sensor's points come column by column, often a whole column at one time: the
    // blended pose is worked out once for a run of equal times.
    const float time = times_s[i];
    std::size_t end = i + 1;
    while (end < n && times_s[end] == time) ++end;
    const float u = std::clamp(float(time / t_end), 0.f, 1.f) * kSteps;
    const int k = std::min(int(u), kSteps - 1);
    const float w = u - float(k);
    const Eigen::Matrix<float, 3, 4> T = (1.f - w) * table[k] + w * table[k + 1];
    const Eigen::Matrix3f R = T.leftCols<3>();
    const Eigen::Vector3f t = T.col(3);
    for (; i < end; ++i) {
      auto& p = out.points[i];
      if (!p.is_valid()) continue;
      const Eigen::Vector3f q = R * p.xyz() + t;
      p.x = q.x();
      p.y = q.y();
      p.z = q.z();
    }
  }
  return out;
}

}  // namespace fieldlidar::odometry
