// Angle wrapping for planar poses, and planar poses of 3D ones.

#include "fieldlidar/core/pose2.hpp"

#include <cmath>
#include <numbers>

namespace fieldlidar {

double wrap_angle(double a_rad) {
  const double a = std::remainder(a_rad, 2.0 * std::numbers::pi);  // [-pi, pi], exact
  return a == -std::numbers::pi ? std::numbers::pi : a;
}

Pose2 planar(const Pose& T) {
  return {T.translation().x(), T.translation().y(), yaw_of(T)};
}

Eigen::Isometry2d isometry_2d(const Pose2& p) {
  Eigen::Isometry2d T = Eigen::Isometry2d::Identity();
  T.translation() = p.xy();
  T.linear() = Eigen::Rotation2Dd(p.yaw_rad).toRotationMatrix();
  return T;
}

}  // namespace fieldlidar
