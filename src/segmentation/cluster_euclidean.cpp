// seed 002, step c: Euclidean clustering of the non-ground points.
//
// Both searches compute the same relation as pcl::EuclideanClusterExtraction over a FLANN k-d
// tree: points i and j are linked when (xi-xj)^2 + (yi-yj)^2 + (zi-zj)^2, evaluated in float in
// that order, is below float(tolerance^2); the clusters are the connected components, kept when
// their size is within [min_points, max_points].

//
// The steps, in cluster_*.cpp: the points taking part (gather), then their connected components
// by the voxel-cell search (grid) or, beyond its coordinate range or on request, the k-d tree
// (kdtree), then the clusters built from them (cluster_common).

#include <cmath>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "cluster_common.hpp"
#include "cluster_euclidean_steps.hpp"
#include "fieldlidar/core/error.hpp"
#include "fieldlidar/segmentation/clustering.hpp"

namespace fieldlidar::segmentation {

ClusterResult cluster_euclidean(const PointCloud& cloud, std::span<const std::uint8_t> skip,
                                const EuclideanClusterConfig& config) {
  if (!(config.tolerance_m > 0) || !std::isfinite(config.tolerance_m))
    throw Error("euclidean clustering: tolerance_m = " + std::to_string(config.tolerance_m) +
                " must be a positive distance");
  if (!skip.empty() && skip.size() != cloud.size())
    throw Error("euclidean clustering: skip has " + std::to_string(skip.size()) +
                " entries for a cloud of " + std::to_string(cloud.size()) + " points");
  // pcl::KdTreeFLANN::radiusSearch hands FLANN static_cast<float>(radius * radius).
  const auto r2 = static_cast<float>(config.tolerance_m * config.tolerance_m);
  std::size_t count = 0;
  const detail::Active active = detail::gather(cloud, skip);
  std::optional<std::vector<std::int32_t>> component;
  if (config.search == EuclideanClusterConfig::Search::kGrid)
    component = detail::components_grid(active, config.tolerance_m, r2, count);
  if (!component) component = detail::components_kdtree({active.xyz.get(), active.size}, r2, count);
  return make_clusters(cloud.size(), {active.index.get(), active.size},
                       {active.xyz.get(), active.size}, *component, count, config.min_points,
                       config.max_points);
}

}  // namespace fieldlidar::segmentation
