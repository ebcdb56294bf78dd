#pragma once
/// \file One scan's valid returns in the map frame with their ground flags, within the map's range
/// of the sensor: what both the single-scan map and the fused map take in. Internal to terrain/.

#include <cstdint>
#include <vector>

#include "fieldlidar/terrain/traversability.hpp"

namespace fieldlidar::terrain {

struct ScanPoints {
  std::vector<Eigen::Vector3d> points_m;  ///< map frame
  std::vector<std::uint8_t> is_ground;
};

/// Ground segmentation in the lidar frame (config.ground), then every valid return placed by
/// T_map_lidar and kept when within config.max_range_m of the sensor horizontally. An empty or
/// all-invalid scan gives no points.
ScanPoints scan_points_in_map(const PointCloud& scan, const SensorModel& sensor,
                              const Pose& T_map_lidar, const TraversabilityConfig& config);

/// A whole surveyed area: grid ground segmentation (config.ground.grid), then every valid return
/// in the cloud's own frame (relative to its origin_m). An empty cloud gives no points.
ScanPoints area_points(const PointCloud& cloud, const TraversabilityConfig& config);

}  // namespace fieldlidar::terrain
