/// A surveyed area into the fused map's cells in one go, its water (when the survey says where)
/// impassable.
#include <algorithm>
#include <string>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/terrain/terrain_map.hpp"
#include "scan_points.hpp"

namespace fieldlidar::terrain {

Grid2D map_area_fused(const PointCloud& cloud, const FusionConfig& config,
                      std::span<const std::uint8_t> is_water) {
  if (!is_water.empty() && is_water.size() != cloud.size())
    throw Error("terrain survey: " + std::to_string(is_water.size()) + " water flags for " +
                std::to_string(cloud.size()) + " points");
  FusionConfig c = config;
  c.see_through_stride = 0;
  c.obstacle_height_from_plane = true;
  // A survey's cells (3-5 m) are larger than the robot: the rise between two neighbours' mean
  // ground spans metres and is a mean slope like the planes', so it takes their margin.
  c.edge_slope_margin_deg = std::max(c.edge_slope_margin_deg, c.slope_margin_deg);
  c.min_own_plane_points = std::min(c.min_own_plane_points, survey_own_plane_points);
  TerrainMap map(c);
  ScanPoints area = area_points(cloud, c.layers);
  std::vector<Eigen::Vector3d> water;
  if (!is_water.empty()) {  // area_points keeps the valid points in order
    std::size_t k = 0;
    for (std::size_t i = 0; i < cloud.size(); ++i) {
      if (!cloud.points[i].is_valid()) continue;
      if (is_water[i]) area.is_ground[k] = 0, water.push_back(area.points_m[k]);
      ++k;
    }
  }
  // The ground first, then the other returns, measured above the ground planes it gave.
  if (!area.points_m.empty()) {
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (const auto& p : area.points_m) centre += p;
    centre /= double(area.points_m.size());
    for (const std::uint8_t pass : {1, 0}) {
      std::vector<Eigen::Vector3d> pts;
      for (std::size_t k = 0; k < area.points_m.size(); ++k)
        if (area.is_ground[k] == pass) pts.push_back(area.points_m[k]);
      const std::vector<std::uint8_t> flags(pts.size(), pass);
      map.add_points(pts, flags, centre);
    }
  }
  Grid2D out = map.global_map();
  if (water.empty()) return out;
  const GridGeometry& g = out.geometry();
  std::vector<int> count(g.cell_count(), 0);
  for (const auto& p : water)
    if (const auto cell = g.cell_of(p.head<2>())) ++count[g.linear_index(cell->x(), cell->y())];
  const auto impassable = out.layer(layer::kImpassable), tau = out.layer(layer::kTraversability);
  for (std::size_t k = 0; k < count.size(); ++k)
    if (count[k] >= c.layers.min_obstacle_points) impassable[k] = 1.0f, tau[k] = 0.0f;
  return out;
}

}  // namespace fieldlidar::terrain
