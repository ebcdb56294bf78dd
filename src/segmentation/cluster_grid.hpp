#pragma once
// The voxel-cell search of the Euclidean clustering in three steps: the points' cells grouped
// into columns (ix, iy), the points sorted into their cells in (ix, iy, iz) order, and the cells
// linked by union-find. Internal to segmentation/.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "cluster_euclidean_steps.hpp"

namespace fieldlidar::segmentation::detail {

/// Each point's cell: its column (a cell index pair (ix, iy)) and its height index iz.
struct GridColumns {
  std::unique_ptr<std::uint32_t[]> col_of;  ///< per point: column id (in order of first point)
  std::unique_ptr<std::int32_t[]> iz_of;    ///< per point: cell index along z
  std::vector<std::int32_t> cix, ciy, col_zlo, col_zhi;  ///< per column id: ix, iy, iz range
  std::vector<std::uint32_t> col_count;                  ///< per column id: points
  bool far = false;  ///< a cell index beyond +-2^30 (some 3e8 m at 0.5 m): search unusable
};

/// Cells of side tolerance/sqrt(3) (slightly less): all points of a cell are linked.
GridColumns assign_columns(const Active& active, double tolerance);

/// The points sorted by (column, iz, k) into cells, the runs of one (column, iz); columns ranked
/// in (ix, iy) order.
struct GridCells {
  std::vector<std::int32_t> sx, sy;             ///< per column rank: ix, iy
  std::vector<std::uint32_t> col_cell;          ///< per column rank: first cell; column count + 1
  std::vector<std::uint32_t> cell_start;        ///< per cell: first item; cell count + 1
  std::vector<std::int32_t> cell_iz;            ///< per cell: iz
  std::unique_ptr<std::uint32_t[]> item_point;  ///< point k of each item, in that order
};

/// The cells of `columns` (whose col_of it overwrites) for its n points (n > 0).
GridCells sort_into_cells(GridColumns& columns, std::size_t n);

/// Links the cells (neighbouring cells, offsets up to +-2, by their first close pair) and labels
/// the points of `active` with their component, numbered in order of their first point.
std::vector<std::int32_t> link_cells(const Active& active, const GridCells& cells, float r2,
                                     std::size_t& count);

}  // namespace fieldlidar::segmentation::detail
