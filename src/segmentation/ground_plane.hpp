#pragma once
// The ground plane near the sensor, from the lowest returns around it. Internal to segmentation/.

#include <span>

#include <Eigen/Core>

#include "fieldlidar/core/point_cloud.hpp"

namespace fieldlidar::segmentation {

/// z = a x + b y + c in the lidar frame (m); the sensor is -c above it (along z).
struct NearGroundPlane {
  double a = 0, b = 0, c = 0;
  bool found = false;
  std::size_t support = 0;  ///< cells that agree with the plane
  double height_at(double x, double y) const { return a * x + b * y + c; }
};

/// Lowest return of each cell of a coarse polar grid (36 sectors x 1 m rings between
/// inner_m and near_range_m), then a trimmed least-squares plane through them: cells blocked by
/// objects (lowest return high) and stray low returns are trimmed away. The tilt is limited to
/// max_tilt_rad so that a wall cannot become the ground.
NearGroundPlane fit_near_ground_plane(const PointCloud& cloud, double near_range_m,
                                      double max_tilt_rad = 0.35, double inner_m = 1.5);
/// The same trimmed fit through given lowest returns (one per cell, x y z in m).
NearGroundPlane fit_plane_to_lows(std::span<const Eigen::Vector3f> lows, double max_tilt_rad);

}  // namespace fieldlidar::segmentation
