// Voxel-cell search, step 3: union-find over the cells, neighbouring cells (offsets up to +-2)
// linked by their first close pair, and the points labelled with their cell's set.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "cluster_box.hpp"
#include "cluster_grid.hpp"

namespace fieldlidar::segmentation::detail {

std::vector<std::int32_t> link_cells(const Active& active, const GridCells& cells, float r2,
                                     std::size_t& count) {
  const std::size_t n = active.size;
  const std::size_t ncols = cells.sx.size();
  const auto &sx = cells.sx, &sy = cells.sy;
  const auto& col_cell = cells.col_cell;
  const auto& cell_start = cells.cell_start;
  const auto& cell_iz = cells.cell_iz;
  const auto point_of = [&](std::size_t item) { return cells.item_point[item]; };
  const std::size_t ncells = cell_start.size() - 1;
  std::vector<std::int32_t> comp(n);
  // Coordinates in item order for cache-friendly pair tests, and each cell's bounds.
  auto sorted = scratch<Xyz>(n);
  for (std::size_t k = 0; k < n; ++k) sorted[k] = active.xyz[point_of(k)];
  auto bounds = scratch<Box>(ncells);
  for (std::size_t cell = 0; cell < ncells; ++cell) {
    Box& b = bounds[cell];
    b.lo = b.hi = sorted[cell_start[cell]];
    for (std::uint32_t k = cell_start[cell] + 1; k < cell_start[cell + 1]; ++k) b.add(sorted[k]);
  }
  // Bounds decide most cell pairs without a pair test: the distance between two boxes, in float
  // with the pair test's operations, bounds every pair's below (rounding is monotonic); a margin of
  // 1e-5 keeps that true should the compiler fuse the multiply-adds differently.
  const float r2_far = r2 * (1.f + 1e-5f), r2_near = r2 * (1.f - 1e-5f);
  DisjointSets sets(ncells);
  auto try_link = [&](std::uint32_t a, std::uint32_t b) {
    if (sets.find(a) == sets.find(b)) return;
    const Box &ba = bounds[a], &bb = bounds[b];
    if (ba.gap2(bb) >= r2_far) return;
    if (ba.span2(bb) < r2_near) {
      sets.unite(a, b);
      return;
    }
    for (std::uint32_t i = cell_start[a]; i < cell_start[a + 1]; ++i) {
      if (bb.gap2(sorted[i]) >= r2_far) continue;
      for (std::uint32_t j = cell_start[b]; j < cell_start[b + 1]; ++j)
        if (squared_distance(sorted[i], sorted[j]) < r2) {
          sets.unite(a, b);
          return;
        }
    }
  };
  // Cells of columns c and d (d a neighbour column) within two steps in z.
  const auto link_columns = [&](std::size_t c, std::size_t d) {
    const std::uint32_t c0 = col_cell[c], c1 = col_cell[c + 1];
    const std::uint32_t d0 = col_cell[d], d1 = col_cell[d + 1];
    std::uint32_t lo = d0;
    for (std::uint32_t a = c0; a < c1; ++a) {
      while (lo < d1 && cell_iz[lo] < cell_iz[a] - 2) ++lo;
      for (std::uint32_t b = lo; b < d1 && cell_iz[b] <= cell_iz[a] + 2; ++b) try_link(a, b);
    }
  };
  // Neighbour columns in one half-plane (the other half sees this column from its side): iy + 1
  // and iy + 2 in the same row, iy - 2 .. iy + 2 in rows ix + 1 and ix + 2. Columns are in (ix, iy)
  // order, so the first candidate of each neighbour row only moves forward.
  // Same column first: cells one or two steps apart in z. A column whose cells all end up in
  // one set is whole; between two whole columns already in one set there is nothing to test.
  std::vector<std::uint8_t> whole(ncols);
  for (std::size_t c = 0; c < ncols; ++c) {
    const std::uint32_t c0 = col_cell[c], c1 = col_cell[c + 1];
    for (std::uint32_t a = c0; a < c1; ++a)
      for (std::uint32_t b = a + 1; b < c1 && cell_iz[b] - cell_iz[a] <= 2; ++b) try_link(a, b);
    bool one = true;
    for (std::uint32_t a = c0 + 1; a < c1 && one; ++a) one = sets.find(a) == sets.find(c0);
    whole[c] = one;
  }
  const auto visit = [&](std::size_t c, std::size_t d) {
    if (whole[c] && whole[d] && sets.find(col_cell[c]) == sets.find(col_cell[d])) return;
    link_columns(c, d);
  };
  std::size_t next_row[3] = {0, 0, 0};
  for (std::size_t c = 0; c < ncols; ++c) {
    for (std::size_t d = c + 1; d < ncols && sx[d] == sx[c] && sy[d] <= sy[c] + 2; ++d) visit(c, d);
    for (int dx = 1; dx <= 2; ++dx) {
      const std::int32_t row = sx[c] + dx, first = sy[c] - 2, last = sy[c] + 2;
      std::size_t& d = next_row[dx];
      while (d < ncols && (sx[d] < row || (sx[d] == row && sy[d] < first))) ++d;
      for (std::size_t e = d; e < ncols && sx[e] == row && sy[e] <= last; ++e) visit(c, e);
    }
  }
  // Each point gets its cell's root, then the roots are numbered in order of their first point.
  for (std::uint32_t cell = 0; cell < ncells; ++cell) {
    const auto root = std::int32_t(sets.find(cell));
    for (std::uint32_t k = cell_start[cell]; k < cell_start[cell + 1]; ++k)
      comp[point_of(k)] = root;
  }
  std::vector<std::int32_t> number(ncells, -1);
  for (std::int32_t& c : comp) {
    std::int32_t& id = number[std::size_t(c)];
    if (id < 0) id = std::int32_t(count++);
    c = id;
  }
  return comp;
}

}  // namespace fieldlidar::segmentation::detail
