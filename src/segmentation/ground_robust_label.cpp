// The points of the robust ground: those of each cell near its ground plane (or, in a rejected
// cell, near the ground expected from its neighbours).

#include <cmath>
#include <cstdint>
#include <vector>

#include "ground_robust_cells.hpp"

namespace fieldlidar::segmentation::detail {

// A ground cell too rough or too cluttered keeps fewer of its points; a pit's walls and rim are
// ground on sparse beam tables.
void label_ground_points(const PolarCells& cells, const std::vector<CellFit>& fits,
                         const RobustGroundConfig& config, bool sparse_rings,
                         GroundResult& result) {
  const float above = float(config.ground_above_m), below = float(config.ground_below_m);
  const float clutter_top = float(config.clutter_height_m);
  const float cluttered_above = float(config.cluttered_above_m);
  const float rejected_above = float(config.rejected_above_m);
  const float rim_above = sparse_rings ? float(config.rim_above_m) : -1.f;
  for (std::size_t c = 0; c < fits.size(); ++c) {
    const CellFit& fit = fits[c];
    if (fit.state == CellState::kEmpty) continue;
    if (config.max_roughness_m > 0 && fit.state == CellState::kGround) {
      double sq = 0;
      std::size_t n = 0;
      for (const CellPoint& p : cells.points(c)) {
        const float h = fit.height_above(p);
        if (std::abs(h) < 0.3f) {
          sq += double(h) * h;
          ++n;
        }
      }
      if (n >= 3 && std::sqrt(sq / double(n)) > config.max_roughness_m) continue;
    }
    float cell_above = fit.state == CellState::kGround ? above : rejected_above;
    if (config.max_clutter_ratio > 0 && fit.state == CellState::kGround) {
      std::size_t low = 0, clutter = 0;
      for (const CellPoint& p : cells.points(c)) {
        const float h = fit.height_above(p);
        if (h <= above)
          ++low;
        else if (h <= clutter_top)
          ++clutter;
      }
      if (double(clutter) > config.max_clutter_ratio * double(low)) cell_above = cluttered_above;
    }
    // A pit or ditch whose bottom holds the cell's low points: its walls and rim, up to the
    // ground expected from the inner cells, are ground however far above the bottom.
    const bool pit_walls = fit.state == CellState::kGround && rim_above >= 0;
    const auto pts = cells.points(c);
    const auto idx = cells.members(c);
    for (std::size_t k = 0; k < pts.size(); ++k) {
      const CellPoint& p = pts[k];
      const std::uint32_t i = idx[k];
      const float h = fit.height_over_ground(p);
      if (h >= -below && (h <= cell_above || (pit_walls && p.z - fit.predicted <= rim_above))) {
        result.is_ground[i] = 1;
        ++result.ground_count;
      }
    }
  }
}

}  // namespace fieldlidar::segmentation::detail
