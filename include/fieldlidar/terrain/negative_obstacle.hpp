#pragma once
/// \file Negative obstacles (ditches, trenches, holes) seen from afar by a spinning LiDAR: the
/// inside of a ditch is a range shadow, so a map built from returns leaves it unknown until the
/// robot looks down into it. What the scan does show is where the ground stops: along one azimuth
/// the returns climb out over the ground at the near lip's level, then a beam meant to meet the
/// ground there comes back from below it (the far wall, farther away than the ground would have
/// been), and the next ones from the ground beyond, back up near the lip's level. The ground under
/// that beam, between where it crossed the near ground's line and where it returned, is hidden
/// and lower than the beam: a likely negative obstacle until seen.
///
/// Telling it from other shadows (the `TrenchShadow` rule): behind a rock or bush the beam ends
/// on the obstacle, above the ground, and the ground beyond continues the near ground; over a
/// hill's crest or down the far side of a slope the returns beyond sink deeper and deeper below
/// the near ground's line and never come back up (nor does a plain crest's curvature). Only a
/// return sunk below the near ground followed by ground risen back towards it is a trench.

#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>

namespace fieldlidar::terrain {

struct NegativeObstacleConfig {
  bool enabled = true;
  /// Returns are grouped by azimuth about the sensor into columns this wide (deg): about one or
  /// two columns of a spinning sensor (0.2 deg on a VLP-16 at 10 Hz), so that a column holds one
  /// return per beam.
  double column_width_deg = 0.4;
  /// A return is sunk when it lies this far (m) below the line of the near ground (the last two
  /// ground returns of its column before it, slope clamped to the robot's max_slope) at its
  /// range. Above the sensor's range noise times the beam's slope and the rolling ground's
  /// curvature over a few metres.
  double min_depth_m = 0.08;
  /// ... plus what ground curving this much (1/m) sinks below the line over the distance d
  /// from its last ground return (curvature / 2 * d^2): a convex swell is no trench. Half the
  /// simulated scene's rolling-ground bound (0.6 m * (0.07^2 + 0.09^2) = 0.008 per m): on the
  /// seed-0 pairs 0 kept a swell by ne_to_hill's start (1.013 -> 1.032) and the full bound hid
  /// most of the ditch (round_ditch 1.369); 0.004 gives 1.013 and 1.120.
  double ground_curvature_per_m = 0.004;
  /// The ground beyond must rise back: its depth below the near line at most this share of the
  /// deepest sunk return's (a descent only sinks deeper).
  double max_far_depth_share = 0.5;
  /// ... and stand at most this far (m) above the near line (higher "ground" is an obstacle's
  /// top the ground segmentation kept).
  double max_far_rise_m = 0.1;
  /// A return is judged sunk only this far (m) beyond the near line's last ground return:
  /// farther, the rolling ground's curvature alone sinks it as much (at 18 m from a VLP-16 at
  /// 1.2 m, 8 m beyond the ring before). The far ground must come within this of the last sunk
  /// return; a return beyond both starts a new line.
  double max_extrapolation_m = 6.0;
  /// Returns nearer than this (m, horizontally) are left out (the robot's own body).
  double min_range_m = 1.0;
  /// A hidden span no longer than this (m) along the ray (a wider gap with the far side risen
  /// back is an undulation, not a trench a robot could fall into).
  double max_span_m = 4.0;
};

/// The hidden ground under one sunk beam: from where it crossed the near ground's line to where
/// it returned, in the map frame (xy, m), with the beam's depth below that line at its return.
struct TrenchShadow {
  Eigen::Vector2d from_m = Eigen::Vector2d::Zero();
  Eigen::Vector2d to_m = Eigen::Vector2d::Zero();
  float depth_m = 0.0f;
};

/// What one scan shows: its trench shadows, and the returns judged level ground (on the line of
/// the ground before them, within min_depth_m, no obstacle in the cell): ground seen there, so no
/// trench, whatever an earlier shadow suggested.
struct TrenchScan {
  std::vector<TrenchShadow> shadows;
  std::vector<std::uint32_t> level_ground;  ///< indices into the scan's returns
};

namespace detail {

/// One return of a column: horizontal range and height (m, from the sensor's foot), its index.
struct ColumnReturn {
  float r, z;
  std::uint32_t index;
  bool ground;
};

/// A sunk return waiting for the ground beyond to rise back: where its beam crossed the near
/// ground's line (range, m), where it returned, and its depth below that line there.
struct Sunk {
  float r_cross, r, z, depth;
  std::uint32_t index;
};

/// The azimuth column (of `columns`, each column_rad wide, from azimuth -pi) of the horizontal
/// offset (dx, dy), exactly int((atan2(dy, dx) + pi) / column_rad) clamped to columns - 1: by a
/// polynomial arctangent (within 1e-5 rad), and by std::atan2 itself within 1e-4 rad of a
/// column's edge. (dx, dy) must not be (0, 0).
int azimuth_column(double dx, double dy, double column_rad, int columns);

}  // namespace detail

/// Working space of find_trench_shadows kept between scans, so that a map's updates allocate
/// nothing for it once warm; what it holds between calls means nothing.
struct TrenchScratch {
  std::vector<std::int32_t> column_of;
  std::vector<std::uint32_t> start, fill;
  std::vector<detail::ColumnReturn> by_index, sorted;
  std::vector<detail::Sunk> sunk;
};

/// The trench shadows of one scan: returns in the map frame (z up) with their ground flags, seen
/// from sensor_m; max_slope_deg bounds the near ground's slope. Non-finite returns are skipped.
TrenchScan find_trench_shadows(std::span<const Eigen::Vector3d> points_m,
                               std::span<const std::uint8_t> is_ground,
                               const Eigen::Vector3d& sensor_m, double max_slope_deg,
                               const NegativeObstacleConfig& config);

/// The same, with its working space in `scratch`.
TrenchScan find_trench_shadows(std::span<const Eigen::Vector3d> points_m,
                               std::span<const std::uint8_t> is_ground,
                               const Eigen::Vector3d& sensor_m, double max_slope_deg,
                               const NegativeObstacleConfig& config, TrenchScratch& scratch);

}  // namespace fieldlidar::terrain
