// Voxel-cell search of the Euclidean clustering: cells of side tolerance/sqrt(3) (all points of a
// cell are linked), union-find over cells, neighbouring cells (offsets up to +-2) linked by their
// first close pair.

#include <optional>
#include <vector>

#include "cluster_grid.hpp"

namespace fieldlidar::segmentation::detail {

std::optional<std::vector<std::int32_t>> components_grid(const Active& active, double tolerance,
                                                         float r2, std::size_t& count) {
  count = 0;
  GridColumns columns = assign_columns(active, tolerance);
  if (columns.far) return std::nullopt;
  if (active.size == 0) return std::vector<std::int32_t>();
  const GridCells cells = sort_into_cells(columns, active.size);
  return link_cells(active, cells, r2, count);
}

}  // namespace fieldlidar::segmentation::detail
