#pragma once
/// \file Leg and person detection from LiDAR rings (seed 000, steps 2-3).
///
/// A leg seen by one ring of a LiDAR is an arc: the seed projects a cluster's points of ring i onto
/// that ring's plane and computes the path length L_k over the points in scan order, the chord D_k
/// between the first and the last point and the bend Curve = L_k / D_k. The arc is a leg arc when
/// `Curve < delta_c` and `L_min < L_k < L_max`; a cluster is a candidate leg when this holds on
/// several rings. Two candidate legs closer than `dist_max` form a person, located at the mean of
/// the arc midpoints. All positions are in the frame of the input points (usually the sensor
/// frame), x-y plane, metres.

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "fieldlidar/core/point_cloud.hpp"
#include "fieldlidar/core/pose.hpp"
#include "fieldlidar/people/leg_classifier.hpp"
#include "fieldlidar/people/static_background.hpp"

namespace fieldlidar::people {

/// The "learned feature library" of the seed plus the switchable additions.
///
/// The seed's own bounds are the first block; defaults were estimated by `fieldlidar legs-train`
/// on the annotated 2D scans of ../shared/data/legs_2d (see config/legs_default.yaml). The
/// additions (second block) are off when their `use_` flag is false, so that the seed's method can
/// be measured alone.
struct LegDetectorConfig {
  // --- seed 000 ---
  double curve_max = 1.9;             ///< delta_c: an arc is a leg when L_k / D_k < delta_c
  double path_min_m = 0.05;           ///< L_min: lower bound of the path length L_k (m)
  double path_max_m = 0.45;           ///< L_max: upper bound of the path length L_k (m)
  double pair_distance_max_m = 0.60;  ///< dist_max: two legs closer than this form a person (m)
  double range_min_m = 0.3;           ///< S_s: clusters nearer than this are dropped (m, x-y)
  double range_max_m = 15.0;          ///< S_m: clusters farther than this are dropped (m, x-y)
  int min_rings = 2;  ///< "checked on several rings": a 3D leg needs this many leg arcs
  // --- ring segmentation (2D scans and the rings of a 3D cluster) ---
  double segment_jump_m = 0.13;      ///< consecutive points farther apart start a new segment (m)
  double leg_merge_radius_m = 0.15;  ///< arcs of different rings within this form one leg (m)
  /// 3D: a ring's points of one cluster also split where consecutive points are farther apart in
  /// azimuth than this (rad; 0 = off): the beams between them hit something else (the gap between
  /// two legs side by side is narrower than segment_jump_m but shows as missing columns).
  double split_azimuth_gap_rad = 0.0;
  // --- additions beyond the seed (switchable) ---
  /// Path length over points at least this far apart (m; 0 = every point, the seed's formula).
  /// Range noise on densely sampled arcs inflates L_k (2 cm noise on 1 cm spacing triples it);
  /// walking the arc in steps of a few cm measures its shape instead of the noise.
  double path_step_m = 0.0;
  /// Moving average over this many consecutive points (odd; <= 1 = off) before L_k and D_k.
  int smooth_window = 1;
  bool use_min_points = false;
  int min_points = 4;  ///< an arc needs at least this many points
  bool use_chord_max = false;
  double chord_max_m = 0.25;  ///< D_k above this is wider than a leg (m)
  bool use_circle_fit = false;
  double radius_min_m = 0.02;  ///< circle fitted to the arc: radius bounds (m)
  double radius_max_m = 0.15;
  double circle_rms_max_m = 0.02;  ///< rms distance of the arc points to the fitted circle (m)
  bool use_curve_min = false;
  double curve_min = 1.02;  ///< reject nearly straight arcs (walls, fences): L_k / D_k > this
  /// 2D: a leg stands in front of what is behind it: the scan points just before and after the
  /// arc must not be nearer to the sensor than the arc's nearest point minus this (m).
  bool use_background = false;  ///< 2D: drop arcs on the static background (StaticBackground)
  bool use_foreground = false;
  double foreground_margin_m = 0.05;
  /// 2D: learned classifier over segment features (leg_classifier.hpp). When set, it replaces
  /// the bound tests of classify_arc for every segment (the background filter still applies).
  std::shared_ptr<const LegClassifier> classifier;
  /// YAML file of `classifier` (written by legs-train), relative to the legs config's folder;
  /// loading it is the caller's job (the library reads no files). Empty = none.
  std::string classifier_file;
};

/// Bounds for 2D laser scans of legs (0.33 deg resolution, people at 0.5-8 m), as estimated by
/// `fieldlidar legs-train` on the annotated scans of ../shared/data/legs_2d, additions on.
LegDetectorConfig default_2d_legs();
/// `config` with every addition (and the learned classifier) switched off: the seed's method alone.
LegDetectorConfig seed_only(LegDetectorConfig config);

/// Shape of one arc (one ring's points of one segment, in scan order).
struct ArcFeatures {
  std::size_t points = 0;
  double path_m = 0;                                     ///< L_k
  double chord_m = 0;                                    ///< D_k
  double curve = 0;                                      ///< L_k / D_k (infinite when D_k = 0)
  Eigen::Vector2d midpoint_m = Eigen::Vector2d::Zero();  ///< mean of the arc's points
  double circle_radius_m = 0;  ///< least-squares circle (0 when fewer than 3 points)
  double circle_rms_m = 0;
  Eigen::Vector2d circle_center_m = Eigen::Vector2d::Zero();
};

/// Seed 000, step 3, formulas 1)-2): L_k, D_k, Curve of ordered points; plus a circle fit.
/// With `path_step_m` > 0, L_k and D_k are measured over the points kept when walking the arc and
/// skipping points nearer than that to the last kept one (the last point is always kept).
ArcFeatures compute_arc_features(std::span<const Eigen::Vector2d> ordered_points,
                                 double path_step_m = 0.0);

/// Moving average of ordered points over `window` neighbours (shrunk at the ends); <= 1 copies.
std::vector<Eigen::Vector2d> smooth_arc(std::span<const Eigen::Vector2d> ordered_points,
                                        int window);

/// Features of one arc with the detector's preprocessing (smoothing, path step) applied.
ArcFeatures arc_features(std::span<const Eigen::Vector2d> ordered_points,
                         const LegDetectorConfig& config);

/// Splits points in scan order into segments wherever two consecutive points are farther apart
/// than `jump_m`; returns [begin, end) index pairs.
std::vector<std::pair<std::size_t, std::size_t>> split_by_jump(
    std::span<const Eigen::Vector2d> ordered_points, double jump_m);

/// Why an arc was or was not accepted (first failed test), for evaluation and training.
enum class ArcVerdict : std::uint8_t {
  kLeg,
  kTooFewPoints,
  kCurve,
  kPathLength,
  kChord,
  kCircle,
  kStraight,
  kOccluded,
};
ArcVerdict classify_arc(const ArcFeatures& arc, const LegDetectorConfig& config);

struct Leg {
  Eigen::Vector2d position_m = Eigen::Vector2d::Zero();  ///< mean of the arc midpoints
  int rings = 0;                                         ///< rings on which an arc passed
  std::int32_t cluster = -1;  ///< index of the cluster (3D) or segment (2D) it came from
};

struct Person {
  Eigen::Vector2d position_m = Eigen::Vector2d::Zero();  ///< mean of the two legs' positions
  std::array<std::size_t, 2> legs{};                     ///< indices into LegDetection::legs
};

struct LegDetection {
  std::vector<Leg> legs;
  std::vector<Person> people;
  std::size_t arcs_tested = 0;
};

/// True when neither scan neighbour of points [begin, end) is nearer to the sensor than the
/// arc's nearest point minus `margin_m` (the arc is not seen through a gap behind something).
bool in_foreground(std::span<const Eigen::Vector2d> ordered_points, std::size_t begin,
                   std::size_t end, double margin_m);

/// The valid returns of a 2D scan (one ring, in beam order) as points in its plane (m). A laser
/// mounted upside down (`upside_down`: its z axis points down) sweeps clockwise seen from above
/// with its y axis to the right: its points come mirrored (y negated) and in reverse order, as
/// the same laser upright would give them, in the frame of its x axis and the world's up.
std::vector<Eigen::Vector2d> scan_points_2d(const PointCloud& scan, bool upside_down = false);

/// A 2D laser at `T_fixed_sensor` (sensor -> fixed frame) is mounted upside down when its z axis
/// points down: scan_points_2d mirrors its scan back.
inline bool upside_down(const Pose& T_fixed_sensor) {
  return T_fixed_sensor.linear()(2, 2) < 0;
}

/// The finite points of `ordered_points` with a range within [config.range_min_m,
/// config.range_max_m], in their order.
std::vector<Eigen::Vector2d> points_in_range(std::span<const Eigen::Vector2d> ordered_points,
                                             const LegDetectorConfig& config);

/// 2D path: one ring of ordered points (a LaserScan in beam order). Segments are split by jump
/// distance, each segment is one arc; every accepted arc is a leg (one ring: min_rings is not
/// applied). Points outside [range_min_m, range_max_m] are ignored.
/// With `background` given (and `use_background` set), arcs lying on the static background are
/// not legs; the caller updates the background with each scan after detection.
LegDetection detect_legs_2d(std::span<const Eigen::Vector2d> ordered_points,
                            const LegDetectorConfig& config,
                            const StaticBackground* background = nullptr);

/// One arc of a 3D cluster: the points of one ring of one cluster between two splits.
struct RingArc {
  std::int32_t cluster = -1;
  std::uint16_t ring = 0;
  std::vector<std::uint32_t> indices;  ///< point indices into the cloud, in azimuth order
  ArcFeatures features;
};
/// Seed 000, step 3, first part: every arc of every cluster within the range S (no test applied).
std::vector<RingArc> extract_ring_arcs(const PointCloud& cloud,
                                       std::span<const std::vector<std::uint32_t>> clusters,
                                       const LegDetectorConfig& config);

/// 3D path (seed 000, step 3): for each cluster (point indices into `cloud`, e.g. from
/// segmentation) within the range S, for each ring, the cluster's points of that ring are put in
/// azimuth order, split by jump distance, and every piece is tested as an arc; passing arcs of
/// different rings within `leg_merge_radius_m` are one leg, kept when it has `min_rings` arcs.
LegDetection detect_legs_3d(const PointCloud& cloud,
                            std::span<const std::vector<std::uint32_t>> clusters,
                            const LegDetectorConfig& config);

/// Seed 000, step 3, last part: pairs legs closer than dist_max into people (closest pairs first,
/// each leg used once); fills `detection.people`.
void pair_legs(LegDetection& detection, const LegDetectorConfig& config);

}  // namespace fieldlidar::people
