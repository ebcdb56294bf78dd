#pragma once
// The cross-product matrix, shared by the two Levenberg-Marquardt solvers' Jacobians.
// Internal to odometry/.

#include <Eigen/Core>

namespace fieldlidar::odometry::detail {

/// [v]x: skew(v) * w == v.cross(w).
inline Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

}  // namespace fieldlidar::odometry::detail
