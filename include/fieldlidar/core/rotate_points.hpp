#pragma once
/// \file A cloud's valid points turned about its origin (a sensor's frame levelled by a known or
/// estimated tilt); invalid points are left as they are.

#include <Eigen/Core>

#include "fieldlidar/core/point_cloud.hpp"

namespace fieldlidar {

/// p <- R p for every valid point of `cloud` (nothing to do for the exact identity, the rotation
/// a sweep found level is given).
void rotate_points(PointCloud& cloud, const Eigen::Matrix3f& R);

}  // namespace fieldlidar
