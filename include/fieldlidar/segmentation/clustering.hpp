#pragma once
/// \file Clustering of non-ground points: k-d tree Euclidean (seed 002) and range-image region
/// growing (seed 000), one result type.

#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "fieldlidar/core/point_cloud.hpp"
#include "fieldlidar/segmentation/range_image.hpp"

namespace fieldlidar::segmentation {

struct Cluster {
  std::vector<std::uint32_t> indices;                  ///< input point indices, ascending
  Eigen::Vector3f centroid = Eigen::Vector3f::Zero();  ///< m
  Eigen::Vector3f min = Eigen::Vector3f::Zero();       ///< m, axis-aligned bounds
  Eigen::Vector3f max = Eigen::Vector3f::Zero();
  std::size_t size() const { return indices.size(); }
};

/// Clusters ordered by size, largest first (ties: lowest first point index first).
struct ClusterResult {
  std::vector<std::int32_t> cluster_of_point;  ///< per input point, -1 = in no cluster
  std::vector<Cluster> clusters;
};

/// seed 002, step c. Two points are linked when their squared distance, computed in float, is
/// below float(tolerance_m^2); clusters are the connected components. A component is kept when
/// min_points <= size <= max_points (pcl::EuclideanClusterExtraction's rule, so the same settings
/// give the same partition); the seed drops clusters of <= 20 points, hence min_points = 21.
struct EuclideanClusterConfig {
  double tolerance_m = 0.5;
  std::size_t min_points = 21;
  std::size_t max_points = std::numeric_limits<std::size_t>::max();
  enum class Search {
    kGrid,    ///< voxel cells of side tolerance/sqrt(3) (all points in one cell are linked) +
              ///< union-find
    kKdTree,  ///< breadth-first growth with nanoflann k-d tree radius searches, as PCL does
  } search = Search::kGrid;
};

/// Points with skip[i] != 0 (e.g. ground) or invalid points take no part; skip may be empty.
ClusterResult cluster_euclidean(const PointCloud& cloud, std::span<const std::uint8_t> skip,
                                const EuclideanClusterConfig& config = {});

/// seed 000, step 2: region growing over the 4-neighbours of the range image (columns wrap).
/// Two neighbouring returns d1 >= d2 at angular spacing alpha join when
/// beta = atan2(d2 sin(alpha), d1 - d2 cos(alpha)) > min_angle_deg (depth_clustering's criterion)
/// or their distance is below max_gap_m.
struct RangeImageClusterConfig {
  double min_angle_deg = 10.0;
  double max_gap_m = 0.0;       ///< 0 = angle criterion only
  std::size_t min_points = 10;  ///< seed 000 noise threshold: smaller clusters are interference
  std::size_t max_points = std::numeric_limits<std::size_t>::max();
  double min_range_m = 0.0;  ///< S_s: clusters whose centroid is nearer are dropped
  double max_range_m = 1e9;  ///< S_m: clusters whose centroid is farther are dropped
  int max_row_gap = 1;       ///< rows searched up and down (>1 bridges missing returns)
  int max_col_gap = 1;       ///< columns searched left and right
};

ClusterResult cluster_range_image(const PointCloud& cloud, const RangeImage& image,
                                  std::span<const std::uint8_t> skip,
                                  const RangeImageClusterConfig& config = {});

/// Fills centroid and bounds from the indices.
void finish_cluster(const PointCloud& cloud, Cluster& cluster);

}  // namespace fieldlidar::segmentation
