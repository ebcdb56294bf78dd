#pragma once
// The steps of the Euclidean clustering (cluster_euclidean): the points taking part, then their
// connected components by a voxel-cell search or, as a fallback, a k-d tree search. Internal to
// segmentation/.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "cluster_common.hpp"
#include "fieldlidar/core/point_cloud.hpp"

namespace fieldlidar::segmentation::detail {

// Scratch arrays sized for every input point and written before they are read (no zeroing).
template <class T>
std::unique_ptr<T[]> scratch(std::size_t n) {
  return std::make_unique_for_overwrite<T[]>(n);
}

/// The points taking part: input index (ascending) and coordinates.
struct Active {
  std::unique_ptr<std::uint32_t[]> index;
  std::unique_ptr<ClusterPoint[]> xyz;
  std::size_t size = 0;
};

/// The points taking part (not skipped, valid), in ascending order.
Active gather(const PointCloud& cloud, std::span<const std::uint8_t> skip);

/// Voxel-cell search: labels the points (components numbered in order of their first point);
/// nullopt when a cell index would leave the int32 range (coordinates beyond some 3e8 m), where
/// the caller falls back to the k-d tree.
std::optional<std::vector<std::int32_t>> components_grid(const Active& active, double tolerance,
                                                         float r2, std::size_t& count);

/// k-d tree search (nanoflann), breadth-first growth as in the seed and in PCL: the component of
/// each point of `pts`, numbered from 0 in order of their first point; `count` of them.
std::vector<std::int32_t> components_kdtree(std::span<const ClusterPoint> pts, float r2,
                                            std::size_t& count);

}  // namespace fieldlidar::segmentation::detail
