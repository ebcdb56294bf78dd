#pragma once
// Helpers shared by the clustering methods. Internal to segmentation/.

#include <cstdint>
#include <numeric>
#include <span>
#include <vector>

#include "fieldlidar/segmentation/clustering.hpp"

namespace fieldlidar::segmentation {

/// Union-find with path halving and union by size.
class DisjointSets {
 public:
  explicit DisjointSets(std::size_t n) : parent_(n), size_(n, 1) {
    std::iota(parent_.begin(), parent_.end(), 0u);
  }
  std::uint32_t find(std::uint32_t a) {
    while (parent_[a] != a) {
      parent_[a] = parent_[parent_[a]];
      a = parent_[a];
    }
    return a;
  }
  bool unite(std::uint32_t a, std::uint32_t b) {
    a = find(a);
    b = find(b);
    if (a == b) return false;
    if (size_[a] < size_[b]) std::swap(a, b);
    parent_[b] = a;
    size_[a] += size_[b];
    return true;
  }

 private:
  std::vector<std::uint32_t> parent_;
  std::vector<std::uint32_t> size_;
};

/// Builds the result from a per-point component id (-1 = none): components with
/// min_points <= size <= max_points become clusters, ordered by size (largest first, ties by
/// lowest point index).
ClusterResult make_clusters(const PointCloud& cloud, const std::vector<std::int32_t>& component,
                            std::size_t component_count, std::size_t min_points,
                            std::size_t max_points);

/// Coordinates of one point taking part in a clustering (m, the cloud's frame).
struct ClusterPoint {
  float x, y, z;
};

/// The same result from the points taking part only: point k of them is input point active[k]
/// (ascending) at xyz[k], in component component[k]; components are numbered in order of their
/// first point (component c's first point comes before component c+1's), so ties in size keep
/// that order without a look at the points. `cloud_size` is the input cloud's size.
ClusterResult make_clusters(std::size_t cloud_size, std::span<const std::uint32_t> active,
                            std::span<const ClusterPoint> xyz,
                            std::span<const std::int32_t> component, std::size_t component_count,
                            std::size_t min_points, std::size_t max_points);

}  // namespace fieldlidar::segmentation
