// Voxel-cell search, step 2: columns ranked in (ix, iy) order and the points sorted into their
// cells, the runs of one (column, iz).

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include "cluster_grid.hpp"

namespace fieldlidar::segmentation::detail {

GridCells sort_into_cells(GridColumns& columns, std::size_t n) {
  auto& col_of = columns.col_of;
  const auto& iz_of = columns.iz_of;
  const auto &cix = columns.cix, &ciy = columns.ciy;
  const auto &col_zlo = columns.col_zlo, &col_zhi = columns.col_zhi;
  const auto& col_count = columns.col_count;
  // Columns renumbered in (ix, iy) order: neighbours are then found by a merge over that order
  // (sequential reads) instead of look-ups spread over the table.
  const std::size_t ncols = cix.size();
  std::vector<std::uint32_t> rank(ncols), column_id(ncols);
  std::vector<std::int32_t> sx(ncols), sy(ncols);
  std::vector<std::uint32_t> col_start(ncols + 1, 0);
  {
    struct ColumnKey {
      std::uint64_t key;
      std::uint32_t id;
    };
    std::vector<ColumnKey> keys(ncols);
    for (std::size_t c = 0; c < ncols; ++c)
      keys[c] = {(std::uint64_t(std::uint32_t(cix[c]) ^ 0x80000000u) << 32) |
                     (std::uint32_t(ciy[c]) ^ 0x80000000u),
                 std::uint32_t(c)};
    std::sort(keys.begin(), keys.end(),
              [](const ColumnKey& a, const ColumnKey& b) { return a.key < b.key; });
    for (std::size_t r = 0; r < ncols; ++r) {
      const std::uint32_t c = keys[r].id;
      rank[c] = std::uint32_t(r);
      column_id[r] = c;
      sx[r] = cix[c];
      sy[r] = ciy[c];
      col_start[r + 1] = col_start[r] + col_count[c];
    }
  }
  // Points sorted by (column, iz, k): cells are the runs of one (column, iz). When the columns'
  // iz ranges are short (as over the ground), one counting sort over (column, iz) buckets does
  // it; else the points are sorted by column and then each column by (iz, k).
  auto item_point = scratch<std::uint32_t>(n);  // point k of each item, in that order
  std::vector<std::uint32_t> cell_start;        // into the items
  std::vector<std::int32_t> cell_iz;
  std::vector<std::uint32_t> col_cell(ncols + 1, 0);
  cell_start.reserve(n + 1);
  cell_iz.reserve(n);
  std::vector<std::uint32_t> bucket_base(ncols + 1, 0);
  std::uint64_t buckets = 0;
  for (std::size_t r = 0; r < ncols; ++r) {
    const std::uint32_t c = column_id[r];
    bucket_base[r] = std::uint32_t(std::min<std::uint64_t>(buckets, 0xffffffffu));
    buckets += std::uint64_t(std::int64_t(col_zhi[c]) - col_zlo[c] + 1);
  }
  if (buckets <= 4 * std::uint64_t(n) + 4096) {
    bucket_base[ncols] = std::uint32_t(buckets);
    // Bucket of each point (in col_of), counted in runs.
    std::vector<std::uint32_t> start(buckets + 1, 0);
    std::uint32_t run_b = 0, run_count = 0;
    for (std::size_t k = 0; k < n; ++k) {
      const std::uint32_t c = col_of[k];
      const std::uint32_t b = bucket_base[rank[c]] + std::uint32_t(iz_of[k] - col_zlo[c]);
      col_of[k] = b;
      if (b != run_b) {
        start[run_b + 1] += run_count;
        run_b = b;
        run_count = 0;
      }
      ++run_count;
    }
    start[run_b + 1] += run_count;
    for (std::size_t b = 0; b < buckets; ++b) start[b + 1] += start[b];
    // The non-empty buckets, written without a branch (empty and full ones interleave at random).
    cell_start.resize(n + 1);
    cell_iz.resize(n + 1);
    std::size_t cells = 0;
    for (std::size_t r = 0; r < ncols; ++r) {
      col_cell[r] = std::uint32_t(cells);
      const std::int32_t zlo = col_zlo[column_id[r]];
      for (std::uint32_t b = bucket_base[r]; b < bucket_base[r + 1]; ++b) {
        cell_start[cells] = start[b];
        cell_iz[cells] = zlo + std::int32_t(b - bucket_base[r]);
        cells += std::size_t(start[b + 1] > start[b]);
      }
    }
    cell_start.resize(cells);
    cell_iz.resize(cells);
    std::uint32_t cur = 0, pos = start[0];
    for (std::size_t k = 0; k < n; ++k) {
      const std::uint32_t b = col_of[k];
      if (b != cur) {
        start[cur] = pos;
        cur = b;
        pos = start[b];
      }
      item_point[pos++] = std::uint32_t(k);
    }
  } else {
    // Each keyed (iz, k) in one integer so that a column sorts with plain integer compares (iz
    // offset by 2^31 keeps the order of negative heights); filled from each column's end.
    auto items = scratch<std::uint64_t>(n);
    std::vector<std::uint32_t> end(col_start.begin() + 1, col_start.end());
    for (std::size_t k = 0; k < n; ++k)
      items[--end[rank[col_of[k]]]] =
          (std::uint64_t(std::uint32_t(iz_of[k]) ^ 0x80000000u) << 32) | k;
    const auto iz_key = [&](std::size_t item) { return std::uint32_t(items[item] >> 32); };
    for (std::size_t c = 0; c < ncols; ++c) {
      const std::uint32_t b = col_start[c], e = col_start[c + 1];
      std::sort(items.get() + b, items.get() + e);
      col_cell[c] = std::uint32_t(cell_start.size());
      for (std::uint32_t it = b; it < e; ++it)
        if (it == b || iz_key(it) != iz_key(it - 1)) {
          cell_start.push_back(it);
          cell_iz.push_back(std::int32_t(iz_key(it) ^ 0x80000000u));
        }
    }
    for (std::size_t k = 0; k < n; ++k) item_point[k] = std::uint32_t(items[k]);
  }
  col_cell[ncols] = std::uint32_t(cell_start.size());
  cell_start.push_back(std::uint32_t(n));
  return {std::move(sx),         std::move(sy),      std::move(col_cell),
          std::move(cell_start), std::move(cell_iz), std::move(item_point)};
}

}  // namespace fieldlidar::segmentation::detail
