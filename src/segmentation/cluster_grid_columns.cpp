// Voxel-cell search, step 1: each point's cell, its (ix, iy) column numbered in order of first
// point and its iz.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "cluster_box.hpp"
#include "cluster_grid.hpp"
#include "column_table.hpp"

namespace fieldlidar::segmentation::detail {

GridColumns assign_columns(const Active& active, double tolerance) {
  // The cell diagonal stays below the tolerance with margin for float rounding of coordinates.
  const double side = tolerance / std::sqrt(3.0) * (1.0 - 1e-4);
  const double inv = 1.0 / side;
  const std::size_t n = active.size;
  auto col_of = scratch<std::uint32_t>(n);
  auto iz_of = scratch<std::int32_t>(n);
  std::vector<std::int32_t> cix, ciy, col_zlo, col_zhi;  // per column id: ix, iy, iz range
  std::vector<std::uint32_t> col_count;
  bool far = false;  // a cell index beyond +-2^30 (some 3e8 m at 0.5 m)
  const auto cell_index = [&](float v) {
    const double c = double(v) * inv;
    far |= !(std::abs(c) < 1073741824.0);
    const auto t = std::int32_t(std::clamp(c, -1073741824.0, 1073741824.0));
    return t - std::int32_t(double(t) > c);  // floor
  };
  // The cells the points span (floor is monotonic: the cells of the bounds' corners).
  Box points_box{{0.f, 0.f, 0.f}, {0.f, 0.f, 0.f}};
  if (n > 0) points_box.lo = points_box.hi = active.xyz[0];
  for (std::size_t k = 1; k < n; ++k) points_box.add(active.xyz[k]);
  const Xyz &lo = points_box.lo, &hi = points_box.hi;
  // Within 512 cells of the origin (some 150 m at 0.5 m) cell indices in float are exact enough:
  // float(v * inv) is off by at most 512 * 2^-24 of a cell, which widens a cell by 6e-5 of its
  // side, inside the 1e-4 margin; and cheaper than the double path needed beyond.
  const double extent = std::max({-lo.x, -lo.y, -lo.z, hi.x, hi.y, hi.z});
  const bool near = extent * inv < 512.0;
  const auto inv_f = float(inv);
  const auto cell_index_near = [inv_f](float v) {
    const float c = v * inv_f;
    const auto t = std::int32_t(c);
    return t - std::int32_t(float(t) > c);  // floor
  };
  const auto window = [&](float v) { return near ? cell_index_near(v) : cell_index(v); };
  auto table =
      std::make_unique<ColumnTable>(window(lo.x), window(hi.x), window(lo.y), window(hi.y), n);
  // A run of points in one column (a ring sweeping over an object) keeps the column's count and
  // iz range in registers: per-point updates in memory would chain each point to the last.
  std::uint32_t run_id = 0, run_n = 0;
  std::int32_t run_lo = 0, run_hi = 0;
  const auto flush_run = [&] {
    if (run_n == 0) return;
    col_count[run_id] += run_n;
    col_zlo[run_id] = std::min(col_zlo[run_id], run_lo);
    col_zhi[run_id] = std::max(col_zhi[run_id], run_hi);
  };
  // Cell indices first, in a loop of their own (independent per point, so many in flight).
  auto cells_of = scratch<std::int32_t>(3 * n);
  if (near)
    for (std::size_t k = 0; k < 3 * n; ++k) cells_of[k] = cell_index_near((&active.xyz[0].x)[k]);
  else
    for (std::size_t k = 0; k < 3 * n; ++k) cells_of[k] = cell_index((&active.xyz[0].x)[k]);
  for (std::size_t k = 0; k < n; ++k) {
    const std::int32_t ix = cells_of[3 * k], iy = cells_of[3 * k + 1], iz = cells_of[3 * k + 2];
    const auto next = std::int32_t(cix.size());
    const auto id = std::uint32_t(table->insert(ix, iy, next));
    if (id == std::uint32_t(next)) {
      cix.push_back(ix);
      ciy.push_back(iy);
      col_count.push_back(0);
      col_zlo.push_back(iz);
      col_zhi.push_back(iz);
    }
    if (id != run_id) {
      flush_run();
      run_id = id;
      run_n = 0;
      run_lo = run_hi = iz;
    }
    ++run_n;
    run_lo = std::min(run_lo, iz);
    run_hi = std::max(run_hi, iz);
    col_of[k] = id;
    iz_of[k] = iz;
  }
  flush_run();
  table.reset();
  return {std::move(col_of),  std::move(iz_of),   std::move(cix),       std::move(ciy),
          std::move(col_zlo), std::move(col_zhi), std::move(col_count), far};
}

}  // namespace fieldlidar::segmentation::detail
