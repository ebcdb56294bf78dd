#include "beam_grid.hpp"

namespace fieldlidar::sim::detail {

void grid_to_cloud(BeamGrid& grid, const std::vector<SimBeam>& beams, const SimConfig& config,
                   double stamp_s, PointCloud& cloud) {
  // Every cell gets its ring and firing time, valid or not (organized output keeps them all).
  for (const auto& b : beams) {
    Point& p = grid.points[grid.cell(b)];
    p.ring = b.ring;
    p.time = b.time_s;
  }

  cloud.stamp_s = stamp_s;
  cloud.fields = PointFields{true, true, true, true};
  cloud.labels.reserve(grid.points.size());
  cloud.points.reserve(grid.points.size());
  if (config.order == PointOrder::kRingMajor) {
    for (std::size_t cell = 0; cell < grid.points.size(); ++cell)
      if (config.organized || grid.valid[cell]) {
        cloud.points.push_back(grid.points[cell]);
        cloud.labels.push_back(grid.labels[cell]);
      }
  } else {
    for (const auto& b : beams) {
      const std::size_t cell = grid.cell(b);
      if (config.organized || grid.valid[cell]) {
        cloud.points.push_back(grid.points[cell]);
        cloud.labels.push_back(grid.labels[cell]);
      }
    }
  }
  const auto rings = std::uint32_t(grid.rings), columns = std::uint32_t(grid.columns);
  if (config.organized) {
    cloud.width = config.order == PointOrder::kRingMajor ? columns : rings;
    cloud.height = config.order == PointOrder::kRingMajor ? rings : columns;
  } else {
    cloud.width = static_cast<std::uint32_t>(cloud.points.size());
    cloud.height = 1;
  }
}

}  // namespace fieldlidar::sim::detail
