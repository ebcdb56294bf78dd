// Pass 1 of the robust ground: per sector from the sensor outward, a cell is ground when its
// low-point plane is upright and flat and continues the ground of the inner cells (or, before
// any, the prior plane near the sensor).

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "ground_robust_cells.hpp"

namespace fieldlidar::segmentation::detail {

double first_cell_rise_m(const RobustGroundConfig& config, double range_m, double blind_radius_m) {
  if (!(config.first_cell_max_rise_m > 0) || !std::isfinite(blind_radius_m)) return 0.0;
  if (!(blind_radius_m > 0)) return config.first_cell_max_rise_m;
  const double q = range_m / blind_radius_m;
  return config.first_cell_max_rise_m * std::min(1.0, q * q);
}

std::vector<CellFit> grow_ground_cells(const PolarGrid& grid, const PolarCells& cells,
                                       const NearGroundPlane& prior,
                                       const RobustGroundConfig& config, bool sparse_rings,
                                       double blind_radius_m) {
  const double max_slope_rad = config.max_slope_deg * std::numbers::pi / 180.0;
  const float max_cos = float(std::cos(max_slope_rad));
  const double tan_slope = std::tan(max_slope_rad);
  const double tan_bend = std::tan(config.max_bend_deg * std::numbers::pi / 180.0);
  // The line continuation is for sparse beam tables, where a cell often holds a single scan
  // line (ground_robust).
  const double tan_line =
      sparse_rings ? std::tan(config.max_line_slope_deg * std::numbers::pi / 180.0) : 0.0;
  std::vector<CellFit> fits(grid.cell_count());
  for (int s = 0; s < grid.sectors(); ++s) {
    const float a_mid = grid.sector_centre_rad(s);
    const float ca = std::cos(a_mid), sa = std::sin(a_mid);
    bool anchored = false;
    double ref_z = 0.0, ref_r = 0.0, ref_grad = 0.0;
    bool ref_line = false;
    bool seen_nearer = false;
    std::size_t ref_cell = 0;
    // Lowest return of the sector farther out than bin b (m): ground seen from the sensor has
    // nothing much lower beyond it in the same direction, unless behind a crest, while a canopy
    // or a hedge top has the ground beyond it.
    const auto lowest_beyond = [&](int b) {
      float z = std::numeric_limits<float>::infinity();
      for (int bb = b + 1; bb < grid.bins(); ++bb) {
        const std::size_t cc = grid.cell(bb, s);
        if (cells.offsets[cc] != cells.offsets[cc + 1])
          z = std::min(z, cells.xyz[cells.lowest[cc]].z);
      }
      return z;
    };
    const auto line_of = [&](std::size_t cc) {
      return line_stats(cells.points(cc), cells.rho.data() + cells.offsets[cc],
                        cells.xyz[cells.lowest[cc]].z + float(config.seed_band_m));
    };
    for (int b = 0; b < grid.bins(); ++b) {
      const std::size_t c = grid.cell(b, s);
      const auto members = cells.points(c);
      if (members.empty()) continue;
      const float r_mid = grid.bin_centre_m(b);
      CellFit& fit = fits[c];
      const PlaneFit plane = fit_cell(members, cells.xyz[cells.lowest[c]].z, config.seed_band_m,
                                      max_cos, r_mid * ca, r_mid * sa, fit);
      double predicted, tolerance;
      if (anchored) {
        const double dr = r_mid - ref_r;
        predicted = ref_z + ref_grad * dr;
        tolerance = config.max_step_m + tan_bend * dr;
      } else {
        predicted = prior.height_at(r_mid * ca, r_mid * sa);
        tolerance = config.max_step_m + tan_slope * std::max(0.0, r_mid - config.near_range_m);
        // The sector's first cell, above the plane: ground hidden in the blind disk (a hill's
        // foot) may have risen off the near plane by the time it is seen, and no nearer cell
        // shows the rise; a raised object has lower ground beyond it, a terrace's step rises
        // more than the cap.
        if (!seen_nearer && fit.elevation > predicted &&
            lowest_beyond(b) >= fit.elevation - float(config.max_step_m))
          tolerance += first_cell_rise_m(config, r_mid, blind_radius_m);
      }
      seen_nearer = true;
      fit.predicted = float(predicted);
      bool continuous = std::abs(fit.elevation - predicted) <= tolerance;
      // Sparse rings far out: a cell holds one scan line, whose plane's tilt is unknown, and a
      // hillside rises by more than the bend tolerance from one line to the next. A line with
      // nothing above it in its cell continues the ground when it rises from the last ground
      // line, at most line_reach_cells cell lengths nearer (not across a shadow), by no more than
      // max_line_slope_deg and nothing beyond it lies lower; the ground then follows that
      // gradient.
      double line_grad = 0;
      bool by_line = false;
      if (!continuous && anchored && plane.line_only && ref_line && tan_line > 0) {
        const LineStats line = line_of(c);
        const double run = double(line.rho) - line_of(ref_cell).rho;
        const double cell_len = cell_length_m(config, r_mid);
        if (line.alone && run > 0.3 && run <= config.line_reach_cells * cell_len) {
          line_grad = (fit.elevation - ref_z) / run;
          by_line = line_grad >= 0 && line_grad <= tan_line &&
                    lowest_beyond(b) >= fit.elevation - float(config.max_step_m);
          continuous = by_line;
        }
      }
      // Behind a crest: the ground between falls out of sight and reappears lower, at least
      // descent_gap_m beyond the last ground cell. The drop continues the ground when it is no
      // steeper than the steepest ground plane and, for a single scan line, nothing stands on the
      // line in its cell (the top of a bush down the slope). Nearer drops are pits: the chain
      // stays at the rim level to reach the far rim.
      if (!continuous && anchored && fit.elevation < std::min(predicted, ref_z) &&
          r_mid - ref_r >= config.descent_gap_m &&
          ref_z - fit.elevation <= config.max_step_m + tan_slope * (r_mid - ref_r) &&
          (!plane.line_only || line_of(c).alone)) {
        continuous = true;
        fit.predicted = fit.elevation;  // no pit walls above the cell's own plane
      }
      const bool flat = plane.flatness <= config.max_flatness_m;
      if (continuous && plane.upright && flat) {
        fit.state = CellState::kGround;
        anchored = true;
        ref_z = fit.elevation;
        ref_r = r_mid;
        ref_line = plane.line_only;
        ref_cell = c;
        // Radial gradient of the cell's plane, to follow a hill outward.
        const double g = -(plane.normal.x() * ca + plane.normal.y() * sa) / plane.normal.z();
        ref_grad = by_line ? line_grad : std::clamp(g, -tan_slope, tan_slope);
      } else {
        fit.state = CellState::kRejected;
      }
    }
  }
  return fits;
}

}  // namespace fieldlidar::segmentation::detail
