// The points taking part in the Euclidean clustering.

#include <cstddef>
#include <cstdint>
#include <span>

#include "cluster_euclidean_steps.hpp"
#include "polar_grid.hpp"

namespace fieldlidar::segmentation::detail {

/// The points taking part (not skipped, valid), in ascending order. Skipped points (the ground)
/// come in runs along a ring, so a branch skips them without reading them; validity is tested
/// without one (valid_point).
Active gather(const PointCloud& cloud, std::span<const std::uint8_t> skip) {
  Active a;
  a.index = scratch<std::uint32_t>(cloud.size());
  std::size_t n = 0;
  const bool all = skip.empty();
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (!all && skip[i] != 0) continue;  // ground comes in runs along a ring: predictable
    const Point& p = cloud.points[i];
    a.index[n] = std::uint32_t(i);
    n += std::size_t(valid_point(p));
  }
  // Coordinates of the points taking part only (a second pass writes a third of the bytes).
  a.size = n;
  a.xyz = scratch<ClusterPoint>(n);
  for (std::size_t k = 0; k < n; ++k) {
    const Point& p = cloud.points[a.index[k]];
    a.xyz[k] = {p.x, p.y, p.z};
  }
  return a;
}

}  // namespace fieldlidar::segmentation::detail
