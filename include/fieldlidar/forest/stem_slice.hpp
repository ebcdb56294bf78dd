#pragma once
/// \file Stem diameters from a thin horizontal slice of a TLS or MLS cloud (a forester's "DBH
/// slice" cut at breast height: one stem, such as TreeLS's dbh.las, or a whole plot's): the
/// slice's points clustered (a stem with its branches is one cluster), and in each cluster
/// circles found by RANSAC and refined on their inliers, so that a branch, a twig or a
/// neighbour's bark does not widen a stem. A plain least-squares circle through every point of
/// such a slice reads the branch into the stem.

#include <cstddef>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "fieldlidar/core/point_cloud.hpp"
#include "fieldlidar/forest/trunks.hpp"

namespace fieldlidar::forest {

struct StemSliceConfig {
  double max_thickness_m = 0.5;  ///< a cloud thicker than this (z extent) is no slice
  double min_radius_m = 0.03;
  double max_radius_m = 1.5;
  double inlier_band_m = 0.01;  ///< a point this near the circle supports it (bark, TLS noise)
  int iterations = 2000;        ///< RANSAC draws of three points (deterministic)
  std::size_t min_points = 20;  ///< points on a stem circle (and in a cluster)
  /// A circle must be seen over this arc (deg): a straight branch fits a wide circle over a
  /// few degrees.
  double min_arc_deg = 90.0;
  double cluster_gap_m = 0.1;     ///< points nearer than this are one cluster
  int max_stems_per_cluster = 4;  ///< stems touching in the slice (a fork, a double stem)
};

struct StemSlice {
  Circle circle;            ///< ok = false when no circle holds min_points inliers
  std::size_t points = 0;   ///< finite points of the slice
  std::size_t inliers = 0;  ///< within inlier_band_m of the circle
  double arc_deg = 0.0;     ///< arc the inliers cover around the centre
  double z_min_m = 0.0, z_max_m = 0.0;
};

/// The z extent of the finite points of `cloud` (m; NaN when it has none).
double slice_thickness_m(const PointCloud& cloud);

/// Whether `cloud` is a thin horizontal slab (finite points spanning at most max_thickness_m
/// in z), as a stem slice is.
bool is_stem_slice(const PointCloud& cloud, const StemSliceConfig& config = {});

/// The best stem circle of a slice (of one stem). Throws fieldlidar::Error for radius bounds
/// that are not 0 < min < max, a band that is not positive or fewer than one iteration.
StemSlice measure_stem_slice(const PointCloud& cloud, const StemSliceConfig& config = {});

/// Every stem of a slice: per cluster of its points, circles one after another (each one's
/// points taken out before the next), kept while a circle holds min_points and min_arc_deg.
/// Ordered by cluster size, largest first. Throws as measure_stem_slice.
std::vector<StemSlice> measure_slice_stems(const PointCloud& cloud,
                                           const StemSliceConfig& config = {});

/// The RANSAC circle of 2D points (the step measure_stem_slice runs on the slice's x, y);
/// `inliers`, when given, receives the points within inlier_band_m of it.
Circle ransac_circle(std::span<const Eigen::Vector2d> points, const StemSliceConfig& config,
                     std::vector<Eigen::Vector2d>* inliers = nullptr);

}  // namespace fieldlidar::forest
