#pragma once
/// \file Distance of a point to a line segment in the plane (metres).

#include <algorithm>

#include <Eigen/Core>

namespace fieldlidar {

/// Distance of `p` to the segment from `a` to `b`; to `a` when the segment is a point.
inline double point_segment_distance(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                                     const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double l2 = ab.squaredNorm();
  const double t = l2 > 0 ? std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

}  // namespace fieldlidar
