#pragma once
/// \file Tree trunks from one scan or plot cloud (seed 003, steps 1-3): scan-line segments,
/// trunk stacks, circle and axis fits, one record per tree with DBH and a quality record.

#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "fieldlidar/core/point_cloud.hpp"

namespace fieldlidar::forest {

/// Step 1: cutting scan lines into segments.
struct ScanSegmentConfig {
  double max_azimuth_gap_deg = 1.0;  ///< a wider gap between neighbours means a missed return
  double max_point_gap_m = 0.15;     ///< neighbours farther apart (3D) are cut apart, plus
  double point_gap_per_m = 0.01;     ///< this much per metre of range (range noise, spacing)
  double max_radius_m = 0.6;         ///< U: segments wider than 2U (a half cylinder) are dropped
  std::size_t min_points = 2;        ///< a slice cluster of a plot cloud
  /// A scan line: a thin stem at range gets one return on most lines (a 10 cm stem at 13 m on a
  /// 1024-column sensor), so one return is a segment.
  std::size_t min_ring_points = 1;
  /// A stem behind a nearer, narrower one is cut in two on each line; the two sides are one
  /// segment again when everything between them is nearer by occluder_gap_m (up to
  /// max_bridged_runs runs of the occluder) and their facing ends lie at ranges one circle can
  /// give (within half their chord plus bridge_range_tolerance_m). 0 runs: no bridging.
  std::size_t max_bridged_runs = 2;
  double occluder_gap_m = 0.3;
  double bridge_range_tolerance_m = 0.1;
  double min_range_m = 0.5;   ///< returns nearer than this (the robot) are ignored
  double max_range_m = 40.0;  ///< and farther than this
  /// Clouds with no ring field: horizontal slices of this thickness replace the scan lines; a
  /// slice is cut into 2D clusters of points no farther apart than slice_link_m.
  double slice_m = 0.15;
  double slice_link_m = 0.08;
};

/// A run of neighbouring returns on one scan line (a ring, or one slice of a plot cloud).
struct ScanSegment {
  std::vector<std::uint32_t> indices;  ///< into the cloud
  int line = 0;                        ///< ring or slice index
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  double width_m = 0.0;  ///< end-to-end extent of its horizontal projection
};

/// Step 1. Points with `excluded[i] != 0` (ground) take no part; `excluded` may be empty.
std::vector<ScanSegment> segment_scan_lines(const PointCloud& cloud,
                                            std::span<const std::uint8_t> excluded,
                                            const ScanSegmentConfig& config = {});

/// Step 2: stacking segments into trunk candidates.
struct StackConfig {
  double max_offset_m = 0.25;  ///< horizontal distance of centroids on neighbouring lines
  int max_line_gap = 8;        ///< lines skipped between two segments of one stack (occlusion)
  double max_step_m = 1.5;     ///< vertical gap between stacked centroids
  std::size_t min_segments = 3;
  double min_extent_m = 0.4;  ///< vertical extent of the centroids
};

/// Indices into `segments` per stack, each ordered by line.
std::vector<std::vector<std::size_t>> stack_segments(std::span<const ScanSegment> segments,
                                                     const StackConfig& config = {});

/// A circle in the horizontal plane.
struct Circle {
  Eigen::Vector2d center = Eigen::Vector2d::Zero();
  double radius_m = 0.0;
  double residual_m = 0.0;  ///< RMS of |distance to centre - radius|
  bool ok = false;
};

/// Step 3: algebraic (Kasa) fit, refined by Gauss-Newton on the geometric distance with the
/// radius clamped to [min_radius_m, max_radius_m]. Fewer than 3 points give ok = false.
Circle fit_circle(std::span<const Eigen::Vector2d> points, double min_radius_m, double max_radius_m,
                  int iterations = 10);

/// Arc covered by points around a centre (deg): 360 less the widest angular gap.
double arc_coverage_deg(std::span<const Eigen::Vector2d> points, const Eigen::Vector2d& center);

/// A 3D line: point and unit direction (pointing up).
struct Axis {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();
  std::vector<std::size_t> inliers;  ///< indices of the centres kept
  bool ok = false;
};

/// Line through circle centres (x, y at height z) by least squares x(z), y(z), dropping centres
/// farther than max(reject_m, 2.5 sigma) from it and refitting. Needs two centres.
Axis fit_axis(std::span<const Eigen::Vector3d> centres, double reject_m = 0.05, int iterations = 5);

/// Step 3 on a whole stem: a straight cylinder through its points.
struct CylinderFitConfig {
  double min_radius_m = 0.03;
  double max_radius_m = 0.6;
  bool fit_direction = true;  ///< false: keep the initial axis direction (short stems)
  int trim_rounds = 3;        ///< refits after dropping points off the surface
  double trim_sigmas = 2.5;   ///< points farther than this many RMS residuals are dropped
  double min_trim_m = 0.02;   ///< but never those nearer than this
  std::size_t min_points = 6;
  /// The start: median of circle fits in bins this tall along the initial axis when there are
  /// three or more (a branch whorl pulls one bin's fit), and points trimmed on the median
  /// absolute residual when it is below the RMS; 0: one fit of all points, RMS trim (sweeps).
  double start_bin_m = 0.3;
};

struct Cylinder {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  ///< a point on the axis
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();
  double radius_m = 0.0;
  double residual_m = 0.0;           ///< RMS distance of the kept points to the surface
  std::vector<std::size_t> inliers;  ///< indices of the points kept
  bool ok = false;
};

/// Gauss-Newton on the distance of each point to the surface, from an initial axis (any point on
/// it, direction up); points off the surface are trimmed. Too few points give ok = false.
Cylinder fit_cylinder(std::span<const Eigen::Vector3d> points, const Eigen::Vector3d& axis_point,
                      const Eigen::Vector3d& axis_direction, const CylinderFitConfig& config = {});

struct TreeConfig {
  ScanSegmentConfig segments;
  StackConfig stacks;
  double min_radius_m = 0.03;
  double max_radius_m = 0.6;
  double max_tilt_deg = 30.0;         ///< axes leaning more than this are not trunks
  double max_residual_m = 0.06;       ///< trees whose stem fit is worse are dropped (RMS, m)
  double plot_max_residual_m = 0.03;  ///< the same for a plot cloud (no rings: TLS/MLS, mm noise)
  double min_arc_deg = 60.0;          ///< and those seen over a narrower arc
  double min_extent_seen_m = 1.0;     ///< and those whose stem points span less height
  /// A sweep's stem whose highest return lies below this height above its base (m; 0 = no such
  /// rule) is dropped when the next scan line up passed over it at its bearing (its returns
  /// there, if any, beyond the stem by top_clear_m): it ends there, a shrub whose rounded top
  /// fits a wide circle at breast height by extrapolation, not a trunk. A stem whose next line
  /// up is blocked, or meets the stem again (a nodding scanner's planes beside it), is kept.
  double min_top_seen_m = 1.3;
  double top_clear_m = 0.2;
  double dbh_height_m = 1.3;        ///< above the ground
  double dbh_window_m = 1.0;        ///< stem points within this of DBH height (along the axis) fit
                                    ///< the cylinder; low branches and twigs are trimmed
  std::size_t min_stem_points = 8;  ///< fewer in the window: not a tree
  double min_fit_span_m = 0.8;      ///< a shorter window span keeps the stacked axis direction
  double max_base_height_m = 3.0;   ///< the lowest segment must be within this of the ground
  /// The share of scan lines (a sweep) or slices (a plot_full_view cloud) between a stem's
  /// lowest and highest that must hold one of its segments (a shrub or crown gives a few
  /// scattered hits over a metre or more).
  double min_line_fill = 0.4;
  /// A cloud without rings scanned from all round (a TLS plot, not one robot sweep whose lower
  /// stems undergrowth hides): its slices must fill min_line_fill too, and a stem whose lowest
  /// point lies more than plot_max_stem_start_m above the ground is a branch or crown piece.
  bool plot_full_view = false;
  double plot_max_stem_start_m = 1.45;
  double ground_radius_m = 1.5;  ///< ground points within this of the axis give its base
  /// A cloud without rings: ground flagged on branches (a cell under a dense crown whose lowest
  /// return is not the floor) is caught as a base more than max_ground_step_m above the lowest
  /// tenth of the ground within ground_check_radius_m, and moved down to it. A sweep with no
  /// ground within ground_radius_m of a stem (its foot hidden) takes the height of the ground
  /// plane fitted within ground_check_radius_m.
  double ground_check_radius_m = 6.0;
  double max_ground_step_m = 1.0;
  double merge_distance_m = 0.3;  ///< stacks whose axes pass this close at DBH are one tree
  double join_distance_m = 0.15;  ///< a stack lying on another's axis (a break) joins it
  CylinderFitConfig cylinder;     ///< radius bounds are taken from min/max_radius_m
  /// A sweep (rings, sensor at the origin): DBH from the stem's silhouette, which range noise
  /// does not bias as it does a fit to a partial arc, and the axis placed on the line of sight
  /// at the returns' mean range plus pi/4 of that radius. The silhouette's two edges over the
  /// lines near breast height are fitted as straight lines through each line's column interval
  /// (between its outermost return and the next column, whose beam passed behind the stem by
  /// edge_clear_m): lines crossing the stem at varied phases of the azimuth step pin the width
  /// to a fraction of a step. With either edge closed on fewer than min_silhouette_lines lines
  /// (an occluder beside it), the per-line widths: angle between the outermost returns plus one
  /// step, mean of the middle half; a line with one edge hidden by a nearer return measures
  /// only when what it sees reaches a step past the axis bearing, otherwise it bounds the width
  /// from below. A stem with fewer measuring lines is dropped, or, when occluded lines saw it,
  /// kept with dbh_uncertain. Plot files always use the fit.
  bool silhouette_dbh = true;
  std::size_t min_silhouette_lines = 2;
  double occluder_gap_m = 0.3;  ///< a return beside a stem's edge this much nearer hides it
  double edge_clear_m = 0.1;    ///< beyond the stem's far side (nearest return + fitted radius)
  /// A stem leaning across the line of sight by more than this slope (tan of the lean) is seen
  /// wider by sqrt(1 + slope^2), which is divided out; a smaller fitted lean is the fit's noise.
  double min_lean_slope = 0.1;
  /// A stem whose every line within dbh_window_m of breast height is cut by an occluder (a
  /// shrub, a low branch, a nearer stem) is measured on its lines up to this far from breast
  /// height, and no lower than silhouette_min_height_m above the ground, that see both of its
  /// edges free (the edge fit, or the per-line widths); the taper over that height is not
  /// corrected. Only with none is the diameter a guess (dbh_uncertain).
  double silhouette_far_window_m = 2.5;
  double silhouette_min_height_m = 0.5;
};

/// One tree: straight trunk from its base on the ground.
struct Tree {
  std::uint32_t id = 0;
  Eigen::Vector3d base_m = Eigen::Vector3d::Zero();  ///< axis point on the ground
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();   ///< unit, up
  double dbh_m = 0.0;
  double z_min_seen_m = 0.0;  ///< visible height range along the axis above the base
  double z_max_seen_m = 0.0;
  double arc_deg = 0.0;          ///< arc of the stem seen around breast height
  double residual_m = 0.0;       ///< RMS circle-fit residual there
  std::size_t observations = 0;  ///< scan lines (segments) on the stem
  bool ground_found = false;     ///< false: base from the lowest stem point
  /// A sweep in which every scan line near breast height sees the stem cut by a nearer occluder
  /// over a sliver too narrow to hold its axis bearing: dbh_m is a guess (the fitted radius, no
  /// less than the visible width), to be left out of an inventory (`fieldlidar trunks` writes
  /// it as an empty dbh_m in trees.csv, null in trees.geojson). A stem seen whole on lines
  /// farther from breast height is measured there and not marked.
  bool dbh_uncertain = false;
  /// Axis point at `h` metres above the base.
  Eigen::Vector3d at_height(double h) const { return base_m + axis * (h / axis.z()); }
};

struct TreeResult {
  std::vector<Tree> trees;
  std::size_t segments = 0;  ///< scan segments kept by step 1
  std::size_t stacks = 0;    ///< stacks kept by step 2
};

/// Steps 1-3 and the per-tree record. `is_ground` (one flag per point, e.g. from
/// segmentation::segment_ground) excludes ground from the segments and places each base.
TreeResult extract_trees(const PointCloud& cloud, std::span<const std::uint8_t> is_ground,
                         const TreeConfig& config = {});

}  // namespace fieldlidar::forest
