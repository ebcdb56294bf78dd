#pragma once
/// \file Training-set augmentation for the 2D leg classifier: each training segment re-seen from
/// farther away and slightly narrower, as a laser with the same angular step would return it.
/// The annotated legs of a few recordings sit at 1-5 m and are seen by one laser at one leg
/// width; legs seen farther, narrower or with fewer points than those are otherwise outside what
/// the classifier has learned (its range and point-count features then reject them).
///
/// Measured on ../shared/data (`legs-train --augment N`, docs/people.md): it does not pay on the
/// shared bags, so legs-train leaves it off. With 2 copies (range x 1..2.5, width x 0.7..0.9, 0.01
/// m noise) negative_2.bag's false legs rise from 0.56 / 0.92 / 0.69 to 2.9 / 3.3 / 3.3 per scan
/// (most beyond 5 m, where no annotated leg lies and the unaugmented classifier's first stump,
/// range_m > 5.1, rejects everything); kept within 5 m, 1.0 / 1.36 / 1.31 with false persons
/// 0 / 0.007 / 0.012 per scan, while the moving-robot bag gains little (MOTA 0.008 -> 0.030,
/// 0.233 -> 0.316 with compact_occupancy_weight 0).

#include <cstdint>
#include <limits>
#include <random>
#include <span>
#include <vector>

#include <Eigen/Core>

namespace fieldlidar::people {

struct SegmentAugmentationConfig {
  int copies = 0;  ///< re-sampled copies added per training segment (0: no augmentation)
  /// Each copy's centroid range is the segment's times a factor drawn log-uniformly in
  /// [range_factor_min, range_factor_max]; copies beyond range_max_m are dropped.
  double range_factor_min = 1.0;
  double range_factor_max = 2.5;
  double range_max_m = 15.0;
  /// Cross-range width (perpendicular to the bearing of the centroid) scaled by a factor drawn
  /// uniformly in [width_factor_min, width_factor_max].
  double width_factor_min = 0.7;
  double width_factor_max = 0.9;
  /// Gaussian noise added to each re-sampled return's range (m).
  double range_noise_m = 0.01;
  /// Angle between consecutive returns (rad); NaN: the median step of the scan's points.
  double angular_step_rad = std::numeric_limits<double>::quiet_NaN();
  std::uint64_t seed = 1;  ///< of the random draws (the same inputs give the same copies)
};

/// A segment re-seen by the augmentation: `points` holds the previous scan neighbour (when the
/// segment had one), the re-sampled returns in [begin, end), then the next neighbour.
struct AugmentedSegment {
  std::vector<Eigen::Vector2d> points;
  std::size_t begin = 0, end = 0;
};

/// Median angle between consecutive points of `scan` (sensor at the origin), 0 when fewer than 2.
double median_angular_step_rad(std::span<const Eigen::Vector2d> scan);

/// The segment [begin, end) of `scan` moved along its centroid's bearing to `range_factor` times
/// its range, its cross-range extent scaled by `width_factor`, and re-sampled by rays
/// `angular_step_rad` apart (first ray at a fraction `phase` (0..1) of a step into the segment,
/// ranges interpolated along the moved points, plus Gaussian noise of `range_noise_m` drawn from
/// `rng`). At least one return is kept. The scan neighbours keep their range offset to the
/// segment and sit one step outside it. Returns no points when the segment is empty.
AugmentedSegment reseen_segment(std::span<const Eigen::Vector2d> scan, std::size_t begin,
                                std::size_t end, double range_factor, double width_factor,
                                double angular_step_rad, double phase, double range_noise_m,
                                std::mt19937_64& rng);

}  // namespace fieldlidar::people
