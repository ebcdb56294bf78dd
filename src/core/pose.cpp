#include "fieldlidar/core/pose.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace fieldlidar {

Trajectory::Trajectory(std::vector<StampedPose> poses) {
  for (const auto& p : poses) push_back(p.stamp_s, p.pose);
}

void Trajectory::push_back(double stamp_s, const Pose& pose) {
  if (!std::isfinite(stamp_s)) throw std::invalid_argument("Trajectory: pose time is not finite");
  if (!poses_.empty() && stamp_s <= poses_.back().stamp_s)
    throw std::invalid_argument("Trajectory: pose time " + std::to_string(stamp_s) +
                                " s is not after the previous " +
                                std::to_string(poses_.back().stamp_s) + " s");
  poses_.push_back({stamp_s, pose});
}

std::optional<Pose> Trajectory::at(double stamp_s) const {
  if (poses_.empty() || stamp_s < poses_.front().stamp_s || stamp_s > poses_.back().stamp_s)
    return std::nullopt;
  auto it = std::lower_bound(poses_.begin(), poses_.end(), stamp_s,
                             [](const StampedPose& p, double t) { return p.stamp_s < t; });
  if (it->stamp_s == stamp_s || it == poses_.begin()) return it->pose;
  const auto& a = *std::prev(it);
  const auto& b = *it;
  return interpolate(a.pose, b.pose, (stamp_s - a.stamp_s) / (b.stamp_s - a.stamp_s));
}

double Trajectory::path_length_m() const {
  double length = 0.0;
  for (std::size_t i = 1; i < poses_.size(); ++i)
    length += (poses_[i].pose.translation() - poses_[i - 1].pose.translation()).norm();
  return length;
}

Pose interpolate(const Pose& a, const Pose& b, double t) {
  const Eigen::Quaterniond qa(a.linear()), qb(b.linear());
  Pose out = Pose::Identity();
  out.linear() = qa.slerp(t, qb).toRotationMatrix();
  out.translation() = (1.0 - t) * a.translation() + t * b.translation();
  return out;
}

double yaw_of(const Pose& pose) {
  const Eigen::Vector3d x = pose.linear().col(0);
  return std::atan2(x.y(), x.x());
}

Eigen::Matrix3d exp_so3(const Eigen::Vector3d& w) {
  const double a = w.norm();
  if (a < 1e-12) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(a, w / a).toRotationMatrix();
}

Pose make_pose(double x, double y, double z, double roll_rad, double pitch_rad, double yaw_rad) {
  Pose p = Pose::Identity();
  p.linear() = (Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(pitch_rad, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(roll_rad, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  p.translation() = Eigen::Vector3d(x, y, z);
  return p;
}

}  // namespace fieldlidar
