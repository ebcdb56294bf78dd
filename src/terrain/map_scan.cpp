/// One scan or one surveyed area into the layered map.
#include <cmath>
#include <vector>

#include "fieldlidar/terrain/traversability.hpp"
#include "scan_points.hpp"

namespace fieldlidar::terrain {

ScanPoints scan_points_in_map(const PointCloud& scan, const SensorModel& sensor,
                              const Pose& T_map_lidar, const TraversabilityConfig& config) {
  ScanPoints out;
  if (scan.valid_count() == 0) return out;
  const Eigen::Vector2d sensor_xy = T_map_lidar.translation().head<2>();
  const auto g = segmentation::segment_ground(scan, sensor, config.ground);
  out.points_m.reserve(scan.size());
  out.is_ground.reserve(scan.size());
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const Point& p = scan.points[i];
    if (!p.is_valid()) continue;
    const Eigen::Vector3d q = T_map_lidar * p.xyz().cast<double>();
    if ((q.head<2>() - sensor_xy).norm() > config.max_range_m) continue;
    out.points_m.push_back(q);
    out.is_ground.push_back(g.is_ground[i]);
  }
  return out;
}

Grid2D map_scan(const PointCloud& scan, const SensorModel& sensor, const Pose& T_map_lidar,
                const TraversabilityConfig& config) {
  voxel_height_m(config);  // validates the robot before any work
  const Eigen::Vector3d sensor_m = T_map_lidar.translation();
  const double r = config.max_range_m;
  // Cell corners on multiples of cell_m, so that maps of successive scans share their cells.
  const Eigen::Vector2d lo =
      ((sensor_m.head<2>().array() - r) / config.cell_m).floor().matrix() * config.cell_m;
  const GridGeometry geometry =
      GridGeometry::covering(lo, sensor_m.head<2>() + Eigen::Vector2d(r, r), config.cell_m);
  const ScanPoints in_map = scan_points_in_map(scan, sensor, T_map_lidar, config);
  return build_layers(in_map.points_m, in_map.is_ground, geometry, config);
}

ScanPoints area_points(const PointCloud& cloud, const TraversabilityConfig& config) {
  ScanPoints out;
  if (cloud.valid_count() == 0) return out;
  const auto g = segmentation::ground_grid(cloud, config.ground.grid);
  out.points_m.reserve(cloud.size());
  out.is_ground.reserve(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Point& p = cloud.points[i];
    if (!p.is_valid()) continue;
    out.points_m.push_back(p.xyz().cast<double>());
    out.is_ground.push_back(g.is_ground[i]);
  }
  return out;
}

Grid2D map_area(const PointCloud& cloud, const TraversabilityConfig& config) {
  voxel_height_m(config);
  const ScanPoints area = area_points(cloud, config);
  Bounds3 b;
  for (const auto& p : area.points_m) b.extend(p);
  const GridGeometry geometry =
      b.empty() ? GridGeometry{.resolution_m = config.cell_m}
                : GridGeometry::covering(b.min.head<2>(), b.max.head<2>(), config.cell_m);
  return build_layers(area.points_m, area.is_ground, geometry, config);
}

}  // namespace fieldlidar::terrain
