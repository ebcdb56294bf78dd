#pragma once
/// \file seed 002, step c: LOAM curvature features on each ring: edges and planar points, strong
/// and weak, chosen per sector.

#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "fieldlidar/core/point_cloud.hpp"

namespace fieldlidar::odometry {

struct FeatureConfig {
  int neighbours = 5;  ///< points on each side along the ring (|S| = 2 * neighbours)
  /// C in [0, 1] over c = |sum_j (X_i - X_j)| / (|S| |X_i|): edge when c >= C (strong when
  /// c >= (1 + C) / 2), planar when c < C (strong when c < C / 2).
  double curvature_threshold = 0.05;
  int sectors = 6;             ///< per ring, as LOAM
  int edges_per_sector = 10;   ///< seed 002: the 10 strongest edge points (topped up from weak)
  int planes_per_sector = 20;  ///< seed 002: the 20 strongest planar points
  double min_range_m = 1.0;
  double max_range_m = 80.0;
  /// A neighbour this much farther/nearer in range than the point, relative to its range, marks an
  /// occlusion boundary: the farther side is not a feature (LOAM's unreliable points).
  double occlusion_ratio = 0.1;
  double max_neighbour_gap_m = 1.0;  ///< a larger step to a ring neighbour cuts the ring there
  /// Every this-many-th planar point that is not selected also goes into the map (1 = all).
  int map_plane_stride = 4;
  /// LidarOdometry matches the selected planar points thinned to one per cube of this side (m),
  /// the first in the strong-before-weak order kept, as LOAM's mapping stage thins a sweep's
  /// features before matching (0 = all matched; a coarse re-alignment always uses them all). On
  /// the ground the 20 points per sector of neighbouring rings crowd together: on a VLP-16
  /// greenhouse sweep 0.2 m keeps 969 of 1582, and matching is half of the sweep's time. With
  /// 0.2 m, greenhouse frames 600-2999 (IMU + wheels): drift 0.221 %, RPE 0.53 cm / 0.060 deg,
  /// ATE 0.020 m (all matched: 0.206 %, 0.48 cm / 0.054 deg, 0.017 m); KITTI ATE 0.141 m (0.142).
  double match_plane_spacing_m = 0.2;
  double match_edge_spacing_m = 0.0;  ///< the same for the selected edge points
};

/// Feature role of a point.
enum class FeatureKind : std::uint8_t { kNone, kWeakPlane, kStrongPlane, kWeakEdge, kStrongEdge };

struct Features {
  std::vector<Eigen::Vector3f> edges;             ///< selected for matching, strong before weak
  std::vector<Eigen::Vector3f> planes;            ///< selected for matching, strong before weak
  std::vector<Eigen::Vector3f> edge_candidates;   ///< every edge point (for the map)
  std::vector<Eigen::Vector3f> plane_candidates;  ///< every planar point (for the map)
};

/// Features of a de-skewed sweep. `rings` gives each point's ring (Point::kNoRing = none); points
/// of one ring are neighbours in index order (scan order). Points with `allowed[i] == 0` are
/// neither features nor neighbours' centre (allowed may be empty); points with `plane_only[i]`
/// (ground) are never edges (may be empty).
Features extract_features(const PointCloud& cloud, std::span<const std::uint16_t> rings,
                          std::span<const std::uint8_t> allowed,
                          std::span<const std::uint8_t> plane_only, const FeatureConfig& config);

/// Keeps the first point of each cube of side `spacing_m` (order kept; spacing_m <= 0: all).
void thin_by_spacing(std::vector<Eigen::Vector3f>& points, double spacing_m);

/// c of seed 002 for every point (-1 where undefined), for tests and tuning.
std::vector<float> curvature(const PointCloud& cloud, std::span<const std::uint16_t> rings,
                             int neighbours);

}  // namespace fieldlidar::odometry
