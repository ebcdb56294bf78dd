// Undergrowth test of the robust ground (dense beam tables): ground returns with low vegetation
// over them and raised above the local ground are leaf litter or a shrub's skirt.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <utility>
#include <vector>

#include "cell_buckets.hpp"
#include "ground_robust_cells.hpp"

namespace fieldlidar::segmentation::detail {

// Undergrowth test (dense beam tables): a ground return on or above its polar cell's plane and
// under_veg_raised_m or more above the local ground -- the lower quartile of the ground returns
// in the 3 x 3 cells of under_veg_ground_cell_m around it, robust to the litter itself -- with at
// least under_veg_min_returns non-ground returns over it (within under_veg_radius_m
// horizontally, under_veg_raised_m to under_veg_top_m higher) lies in leaf litter, under a
// shrub's skirt or in the low crown of a tree, not on the ground. Ground running on under a
// hedge lies at the ground level and is kept. Only the returns of cells with enough low
// vegetation within reach are tested, and the local ground is found once per ground cell.
void reject_under_vegetation(const PolarGrid& grid, const PolarCells& cells,
                             const std::vector<CellFit>& fits, const RobustGroundConfig& config,
                             GroundResult& result) {
  const float radius = float(config.under_veg_radius_m);
  const float raised = float(config.under_veg_raised_m), top = float(config.under_veg_top_m);
  const std::uint32_t min_returns = std::uint32_t(config.under_veg_min_returns);
  const float low_top = top + float(config.ground_above_m);
  const float above_plane = float(config.under_veg_above_plane_m);
  // Non-ground returns low enough over their cell's ground to be over a ground return.
  std::vector<std::uint32_t> low_in(fits.size(), 0);
  std::vector<CellPoint> low_pts;
  for (std::size_t c = 0; c < fits.size(); ++c) {
    const CellFit& fit = fits[c];
    if (fit.state == CellState::kEmpty) continue;
    const auto pts = cells.points(c);
    const auto idx = cells.members(c);
    for (std::size_t k = 0; k < pts.size(); ++k) {
      if (result.is_ground[idx[k]]) continue;
      if (fit.height_over_ground(pts[k]) < low_top) {
        low_pts.push_back(pts[k]);
        ++low_in[c];
      }
    }
  }
  if (low_pts.size() < min_returns) return;
  const int sectors = grid.sectors(), bins = grid.bins();
  const double sector_rad = 2.0 * std::numbers::pi / sectors;
  // Sectors either way that a distance spans at bin b's inner edge.
  const auto sectors_spanned = [&](int b, double distance_m) {
    const double centre = grid.bin_centre_m(b);
    const double inner = std::max(0.5, centre - 0.5 * cell_length_m(config, centre));
    return std::min(sectors / 2, int(std::ceil(distance_m / (inner * sector_rad))));
  };
  // Calls f(cell) for the cells up to bin_span bins and sector_span sectors from (b, s).
  const auto for_cells_around = [&](int b, int s, int bin_span, int sector_span, auto&& f) {
    for (int db = -bin_span; db <= bin_span; ++db)
      if (b + db >= 0 && b + db < bins)
        for (int ds = -sector_span; ds <= sector_span; ++ds)
          f(grid.cell(b + db, (s + ds + sectors) % sectors));
  };
  // Cells with enough of them within reach: one bin and as many sectors either way as
  // under_veg_radius_m spans.
  std::vector<std::uint8_t> within_reach(fits.size(), 0);
  for (int b = 0; b < bins; ++b) {
    const int span = sectors_spanned(b, radius);
    for (int s = 0; s < sectors; ++s) {
      const std::size_t c = grid.cell(b, s);
      if (fits[c].state == CellState::kEmpty) continue;
      std::uint32_t n = 0;
      for_cells_around(b, s, 1, span, [&](std::size_t cc) { n += low_in[cc]; });
      within_reach[c] = n >= min_returns;
    }
  }
  // Ground returns with enough vegetation over them.
  const CellBuckets low(radius, low_pts);
  const float r2 = radius * radius;
  std::vector<std::size_t> covered;        // positions in `cells`
  std::vector<std::size_t> covered_cells;  // their polar cells, once each
  for (std::size_t c = 0; c < fits.size(); ++c) {
    if (!within_reach[c]) continue;
    const std::size_t before = covered.size();
    const CellFit& fit = fits[c];
    for (std::size_t k = cells.offsets[c]; k < cells.offsets[c + 1]; ++k) {
      if (!result.is_ground[cells.order[k]]) continue;
      const CellPoint& p = cells.xyz[k];
      if (fit.state == CellState::kGround && fit.height_above(p) < above_plane) continue;
      std::uint32_t over = 0;
      low.around(low.cell(p.x), low.cell(p.y), [&](const CellPoint& q) {
        const float dz = q.z - p.z, dx = q.x - p.x, dy = q.y - p.y;
        over += dz > raised && dz < top && dx * dx + dy * dy < r2;
        return over < min_returns;
      });
      if (over >= min_returns) covered.push_back(k);
    }
    if (covered.size() > before) covered_cells.push_back(c);
  }
  if (covered.empty()) return;
  // Their height over the local ground, from the ground returns before any is rejected, once
  // per ground cell: those of the polar cells within two ground cells of a covered return, one in
  // kGroundSample (a quartile of hundreds of returns does not need them all).
  constexpr std::size_t kGroundSample = 4;
  const double ground_reach = 2.0 * config.under_veg_ground_cell_m;
  std::vector<std::uint8_t> near_covered(fits.size(), 0);
  for (const std::size_t c : covered_cells) {
    const int b = int(c % std::size_t(bins)), s = int(c / std::size_t(bins));
    const int bin_span = int(std::ceil(ground_reach / cell_length_m(config, grid.bin_centre_m(b))));
    for_cells_around(b, s, bin_span, sectors_spanned(b, ground_reach),
                     [&](std::size_t cc) { near_covered[cc] = 1; });
  }
  std::vector<CellPoint> ground_pts;
  std::size_t seen = 0;
  for (std::size_t c = 0; c < fits.size(); ++c) {
    if (!near_covered[c]) continue;
    for (std::size_t k = cells.offsets[c]; k < cells.offsets[c + 1]; ++k)
      if (result.is_ground[cells.order[k]] && ++seen % kGroundSample == 0)
        ground_pts.push_back(cells.xyz[k]);
  }
  const CellBuckets ground(float(config.under_veg_ground_cell_m), ground_pts);
  const auto cell_of = [&ground, &cells](std::size_t k) {
    return std::pair{ground.cell(cells.xyz[k].x), ground.cell(cells.xyz[k].y)};
  };
  std::sort(covered.begin(), covered.end(),
            [&](std::size_t a, std::size_t b) { return cell_of(a) < cell_of(b); });
  std::vector<float> zs;
  std::vector<std::uint32_t> rejected;
  float base = 0.f;
  for (std::size_t n = 0; n < covered.size(); ++n) {
    const auto [ix, iy] = cell_of(covered[n]);
    if (n == 0 || cell_of(covered[n - 1]) != std::pair{ix, iy}) {
      zs.clear();
      ground.around(ix, iy, [&](const CellPoint& q) {
        if (std::abs(ground.cell(q.x) - ix) <= 1 && std::abs(ground.cell(q.y) - iy) <= 1)
          zs.push_back(q.z);
        return true;
      });
      // Too few ground returns sampled around to tell: not rejected.
      base = std::numeric_limits<float>::infinity();
      if (!zs.empty()) {
        const auto quartile = zs.begin() + std::ptrdiff_t(zs.size() / 4);
        std::nth_element(zs.begin(), quartile, zs.end());
        base = *quartile;
      }
    }
    if (cells.xyz[covered[n]].z - base >= raised) rejected.push_back(cells.order[covered[n]]);
  }
  for (const std::uint32_t i : rejected) {
    result.is_ground[i] = 0;
    --result.ground_count;
  }
}

}  // namespace fieldlidar::segmentation::detail
