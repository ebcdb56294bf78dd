#pragma once
/// \file Rigid poses and timestamped trajectories.
///
/// A pose is an Eigen::Isometry3d named after the frames it connects: `T_world_lidar` maps points
/// from the lidar frame into the world frame (p_world = T_world_lidar * p_lidar).

#include <cstddef>
#include <optional>
#include <vector>

#include <Eigen/Geometry>

namespace fieldlidar {

using Pose = Eigen::Isometry3d;

/// A pose at a time (s).
struct StampedPose {
  double stamp_s = 0.0;
  Pose pose = Pose::Identity();
};

/// Poses in increasing time order.
class Trajectory {
 public:
  Trajectory() = default;
  explicit Trajectory(std::vector<StampedPose> poses);

  /// Appends a pose; throws std::invalid_argument when its time is not after the last one.
  void push_back(double stamp_s, const Pose& pose);
  std::size_t size() const { return poses_.size(); }
  bool empty() const { return poses_.empty(); }
  const StampedPose& operator[](std::size_t i) const { return poses_[i]; }
  const std::vector<StampedPose>& poses() const { return poses_; }
  auto begin() const { return poses_.begin(); }
  auto end() const { return poses_.end(); }

  /// Pose at `stamp_s` by linear/slerp interpolation; nullopt outside the covered time span.
  std::optional<Pose> at(double stamp_s) const;
  /// Sum of translation distances between consecutive poses (m).
  double path_length_m() const;

 private:
  std::vector<StampedPose> poses_;
};

/// Interpolates between two poses: t = 0 gives a, t = 1 gives b (rotation by slerp).
Pose interpolate(const Pose& a, const Pose& b, double t);

/// Yaw (rad) of a pose's x axis in the x-y plane.
double yaw_of(const Pose& pose);

/// The rotation by the rotation vector `w` (axis times angle, rad): SO(3)'s exponential map;
/// identity for a vector shorter than 1e-12.
Eigen::Matrix3d exp_so3(const Eigen::Vector3d& w);

/// Pose from x, y, z (m) and roll, pitch, yaw (rad; applied as Rz(yaw) * Ry(pitch) * Rx(roll)).
Pose make_pose(double x, double y, double z, double roll_rad, double pitch_rad, double yaw_rad);

}  // namespace fieldlidar
