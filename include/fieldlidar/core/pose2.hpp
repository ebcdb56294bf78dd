#pragma once
/// \file Planar poses of a ground robot and angle wrapping (map or world frame, metres, radians).

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "fieldlidar/core/pose.hpp"

namespace fieldlidar {

/// A pose in the ground plane: position (m) and heading yaw (rad, counter-clockwise from +x).
struct Pose2 {
  double x_m = 0.0;
  double y_m = 0.0;
  double yaw_rad = 0.0;
  Eigen::Vector2d xy() const { return {x_m, y_m}; }
};

/// Angle wrapped to (-pi, pi]; NaN for a non-finite angle (never loops on one).
double wrap_angle(double a_rad);

/// The planar pose (x, y, yaw) of a 3D pose.
Pose2 planar(const Pose& T);
/// The 2D rigid transform of a planar pose.
Eigen::Isometry2d isometry_2d(const Pose2& p);

}  // namespace fieldlidar
