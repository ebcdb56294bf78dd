#pragma once
// The returns of one sweep in (ring, column) cells, and their order in the output cloud.

#include <cstdint>
#include <vector>

#include "fieldlidar/core/point_cloud.hpp"
#include "fieldlidar/sim/lidar_simulator.hpp"
#include "simulator_state.hpp"

namespace fieldlidar::sim::detail {

/// One cell per beam, index ring * columns + column; a cell without a return stays all-zero.
struct BeamGrid {
  int rings = 0;
  int columns = 0;
  std::vector<Point> points;
  std::vector<std::uint32_t> labels;
  std::vector<std::uint8_t> valid;

  BeamGrid(int rings_, int columns_)
      : rings(rings_),
        columns(columns_),
        points(std::size_t(rings_) * columns_),
        labels(points.size(), 0),
        valid(points.size(), 0) {}
  std::size_t cell(const SimBeam& b) const { return std::size_t(b.ring) * columns + b.column; }
};

/// The sweep's cloud: every cell gets its beam's ring and firing time, then the cells are emitted
/// in `config.order` (all of them when `config.organized`, else the valid ones only) with the
/// width/height that order implies.
void grid_to_cloud(BeamGrid& grid, const std::vector<SimBeam>& beams, const SimConfig& config,
                   double stamp_s, PointCloud& cloud);

}  // namespace fieldlidar::sim::detail
