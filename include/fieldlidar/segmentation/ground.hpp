#pragma once
/// \file Ground segmentation: four methods behind one call, per-point ground flags.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "fieldlidar/core/point_cloud.hpp"
#include "fieldlidar/core/sensor_model.hpp"
#include "fieldlidar/segmentation/range_image.hpp"

namespace fieldlidar::segmentation {

enum class GroundMethod {
  kRobust,   ///< polar-grid local plane fits grown outward from the sensor (default)
  kSeed000,  ///< seed 000: height difference between neighbouring rows of the range image
  kSeed002,  ///< seed 002: downward beams, ground when H - h <= tolerance
  /// Progressive morphological opening of a lowest-point grid, for clouds that are not one
  /// sensor sweep (airborne or terrestrial surveys, merged maps): no rings, no sensor origin.
  kGrid,
};

/// The grid ground (a simple morphological filter after Pingel et al. 2013, SMRF): the lowest
/// return of each square cell, empty cells filled from their neighbours, then openings of
/// growing square windows; a cell the opening lowers by more than slope * window radius stands
/// on an object. The ground surface is the lowest-point grid without those cells (filled again);
/// a point is ground within [-below_m, above_m + slope_scale * local slope] of it. Works in the
/// cloud's own frame, z up.
struct GridGroundConfig {
  /// Side of a grid cell (m); 0 = from the density: 3 / sqrt(points per m^2 of the cloud's
  /// extent), within [min_cell_m, max_cell_m] (an airborne 1 point/m^2: 3 m; a terrestrial plot:
  /// min_cell_m). A cell needs a few returns for its lowest to be the ground's.
  double cell_m = 0.0;
  double min_cell_m = 0.5;
  double max_cell_m = 4.0;
  double max_window_m = 18.0;        ///< largest opening window (side, m)
  double max_slope = 0.3;            ///< rise over run of the steepest ground between windows
  double above_m = 0.2;              ///< points up to this above the ground surface are ground
  double slope_scale = 0.6;          ///< plus this times the surface's rise over run there (m/m)
  double below_m = 0.5;              ///< and down to this below it (lower: noise)
  double low_outlier_m = 1.0;        ///< a cell this far below its neighbours' median is noise
  std::size_t max_cells = 1u << 24;  ///< larger grids raise fieldlidar::Error (raise cell_m)
};

/// Levelling before the robust ground: a sensor tilted by more than level_tolerance_deg
/// (handheld, on a slope) has its cloud rotated into a frame whose z is the up direction --
/// measured (an IMU's gravity) or the normal of the dominant ground plane below the sensor --
/// and the labels map back to the input points one to one.
struct LevellingConfig {
  bool enabled = true;
  /// Up in the lidar frame (any length): e.g. an accelerometer's reading at rest rotated into
  /// the lidar frame (it measures -gravity). Zero = unknown, estimated from the cloud.
  Eigen::Vector3d up{0, 0, 0};
  double level_tolerance_deg = 8.0;  ///< tilts up to this are left alone (the ground handles them)
  double max_tilt_deg = 45.0;        ///< steepest ground plane the estimate considers
  double near_range_m = 20.0;        ///< the estimate uses the lowest returns nearer than this
  double inlier_band_m = 0.15;       ///< distance of a plane's inliers
  double below_band_m = 0.5;         ///< returns farther below a candidate plane count against it
  int hypotheses = 200;              ///< RANSAC plane hypotheses
};

/// seed 000, step 2: two vertically neighbouring range-image cells (rows below the horizon) are
/// both ground when their height difference is small for their horizontal spacing.
struct Seed000GroundConfig {
  double max_height_step_m = 0.05;  ///< allowed |dz| between neighbouring rows at zero spacing
  double max_slope_deg = 10.0;      ///< plus tan(slope) * horizontal spacing of the two points
  double max_elevation_deg = 0.0;   ///< only beams looking below this elevation take part
  RangeImageConfig image;
};

/// seed 002, step b: a point of a downward beam is ground when H - h <= tolerance_m, with H the
/// mounting height and h the vertical drop from the sensor to the point (h = -z, lidar frame).
struct Seed002GroundConfig {
  double tolerance_m = 0.05;
  double mounting_height_m = 0.0;  ///< H; 0 = SensorModel::mounting_height_m, else estimated
};

/// The robust default: the ground is grown outward over a polar grid of local plane fits.
struct RobustGroundConfig {
  double max_range_m = 120.0;   ///< points farther away are left non-ground
  double sector_deg = 2.8125;   ///< azimuth width of a polar cell (128 sectors)
  double min_cell_m = 1.0;      ///< radial length of the innermost cells
  double cell_growth = 0.06;    ///< radial length = max(min_cell_m, cell_growth * range)
  double seed_band_m = 0.10;    ///< points within this of a cell's low point seed the fit
  double max_slope_deg = 22.0;  ///< steepest ground plane accepted (uprightness)
  double max_step_m = 0.12;     ///< height jump allowed between neighbouring ground cells
  double max_bend_deg = 6.0;    ///< change of slope allowed from one ground cell to the next
  /// Beyond the reach of the plane fits, where a cell holds a single scan line: steepest rise
  /// from one ground line to the next accepted (deg; 0 = off): about the angle of repose of
  /// soil and gravel, steeper is a face. Sensors of up to 32 rings only.
  double max_line_slope_deg = 35.0;
  /// and at most this many cell lengths between the two lines (a longer gap is a shadow).
  double line_reach_cells = 3.0;
  /// A cell lower than the last ground cell of its sector, at least this far beyond it (m), is
  /// the ground falling away behind a crest and continues the ground, down to max_slope_deg
  /// from the last ground cell; nearer, a drop is a pit or a ditch and the ground stays at the
  /// rim level (inf = off).
  double descent_gap_m = 6.0;
  /// The first non-empty cell of a sector, above the prior plane near the sensor, continues
  /// the ground within max_step_m plus first_cell_max_rise_m x min(1, (r / r_b)^2), r the
  /// cell's range and r_b the blind radius (where the lowest beam meets level ground: the
  /// sensor's mounting height, or its height estimated over the prior plane when the mount is
  /// unknown, over the tangent of that beam's depression), when nothing beyond it
  /// in the sector lies lower by more than max_step_m. No ground is seen inside the blind disk,
  /// so the first ground seen at a hill's foot stands above the plane of the flatter ground
  /// around the robot, and every cell beyond it was lost with it (the flank then read as
  /// obstacle returns or as seen ground-less cells, and goals there as blocked); a first cell
  /// nearer than r_b lies on ground already rising towards the sensor and gets the square
  /// law's share (ground curving up from the robot rises as r^2). For a VLP-16 on a 1.2 m mast
  /// (r_b 4.48 m) this is the rule it was chosen with, a curvature of 0.03 / m capped at 0.3 m.
  /// Simulated terrain, the navigate pairs of seeds 6-11 (72 runs), curvature 0 / 0.02 / 0.03 /
  /// 0.05 without the cap: truth-passable cells of the final maps blocked more than 1 m from any
  /// truth obstacle 1299 / 893 / 862 / 743, goals the truth plan reaches that arrived 49 / 52 /
  /// 52 / 52 of 56, drives onto truth-impassable cells 5 / 6 / 5 / 6; with the 0.3 m cap
  /// (0.03): 52 and 5, and the seed-1 terrace's 0.5 m step is no longer taken for a hill's foot
  /// by a pitched sensor (NavigatePairs.PitchedLookRoundTerraceAndDitch: 17 -> 0 frames). Sim
  /// scenes' ground F1 unchanged. The fixed curvature gave a sensor that sees nearer ground
  /// (HDL-32E, r_b 2.0 m) a tenth of the cap at its first cells, and the rule was for sparse
  /// beam tables (up to 32 rings) only, though the blind disk is every sensor's: the navigate
  /// random pairs of seeds 2-21 (184 reachable goals) with the HDL-32E found no path from
  /// starts beside the hill's flank (175 arrived) and with the OS1-64 gave up goals on it (174;
  /// docs/navigate.md has the figures since). The estimated height instead of the mount's, on a
  /// VLP-16 whose mount is known, moved r_b on slopes and lost seed 1's round_hill. 0 = off.
  double first_cell_max_rise_m = 0.3;  ///< m, the most the rule adds to the tolerance
  double max_flatness_m = 0.08;        ///< sqrt of the smallest eigenvalue of a ground fit
  double ground_above_m = 0.15;        ///< points up to this above the local plane are ground
  double ground_below_m = 1.0;         ///< and down to this below it
  /// In a cell that is not ground (an object stands there), points up to this above the ground
  /// expected from the neighbouring cells are still ground (m).
  double rejected_above_m = 0.03;
  /// In a ground cell, returns up to this above the ground expected from the inner cells are
  /// ground however far above the cell's plane: the walls and rim of a pit or ditch whose bottom
  /// holds the cell's low points (m; < 0 = off). Sensors of up to 32 rings only.
  double rim_above_m = 0.0;
  /// Returns between ground_above_m and this height over a cell's plane are clutter (m).
  double clutter_height_m = 1.5;
  /// A cell with more clutter than this times its ground returns is cluttered (0 = off): the
  /// base of a bush or hedge, where only returns very close to the plane are ground.
  double max_clutter_ratio = 0.5;
  double cluttered_above_m = 0.03;  ///< ground_above_m in a cluttered cell (< 0: none is ground)
  /// RMS height (m) of the returns within 0.3 m of a cell's plane above which the cell is
  /// vegetation rather than ground (0 = off).
  double max_roughness_m = 0.0;
  double near_range_m = 12.0;  ///< sensor height estimated from cells nearer than this
  /// Foot-of-a-face test over azimuth columns: two returns of one column, neighbours in
  /// elevation, that rise at least face_min_rise_m at more than face_steep_deg from the
  /// horizontal lie on an object's face (trunk, hedge, shrub base), so the upper one is not
  /// ground, nor the lower one when the pair is steeper than face_foot_deg.
  /// Azimuth columns of the test; 0 = test off; -1 = SensorModel::columns for sensors of up to
  /// 32 rings (VLP-16, HDL-32E: sparse rings, where vegetation bases pass the plane tests), off
  /// for denser ones. With a ring field the count is rounded down to a multiple of the polar
  /// sectors (1800 -> 1792 at the default 2.8125 deg) so that columns nest in sectors.
  int face_columns = -1;
  double face_steep_deg = 60.0;  ///< rise over horizontal spacing of a face (deg)
  double face_foot_deg = 80.0;   ///< the lower return too when the pair is this steep (deg)
  /// Smaller rises are left alone (m): on the dense beams of a 64-ring sensor, grass tufts and
  /// clods rise steeply over a few centimetres between rings (0.3 m measured best on RELLIS-3D
  /// and the simulated scenes together).
  double face_min_rise_m = 0.30;
  int face_neighbours = 2;  ///< returns above each one compared with it
  /// Undercut test of the same columns: when the return above a ground return rises by
  /// face_back_rise_m to face_back_top_m and comes back towards the sensor (its horizontal range
  /// minus the lower one's is within [-face_back_reach_m, face_back_run_m]), the beam above
  /// struck the overhanging flank of a bush or hedge and both returns are that object's, not
  /// ground: over open ground the horizontal range grows by metres from one downward ring to the
  /// next. Branches and canopy overhead rise more and reach farther, and are left alone.
  double face_back_rise_m = 0.06;  ///< m, smallest rise (sensor noise stays well below it)
  double face_back_top_m = 0.6;    ///< m, largest rise
  double face_back_run_m = -0.03;  ///< m, the upper return at least this much nearer
  double face_back_reach_m = 0.3;  ///< m, and at most this much nearer
  /// The lower return of a face or an undercut stays ground when the ground runs on to it: it
  /// lies within face_back_flat_m of the height of the return below it in the column (< 0:
  /// never), at most face_flat_gap_m farther out. Farther, the two are separated by a shadow and
  /// the lower return may as well be the base of a post or trunk (the foot of a bush standing on
  /// open ground is 1-2.5 m beyond the ring below it at 5-15 m on a VLP-16).
  double face_back_flat_m = 0.03;
  double face_flat_gap_m = 2.5;
  /// Undergrowth test, sensors of more than 32 rings: a ground return at least
  /// under_veg_raised_m above the local ground (the lower quartile of the ground returns in the
  /// 3 x 3 square cells of under_veg_ground_cell_m around it) and under_veg_above_plane_m above
  /// its polar cell's plane, with at least under_veg_min_returns non-ground returns over it --
  /// within under_veg_radius_m horizontally, under_veg_raised_m to under_veg_top_m higher -- lies
  /// in leaf litter, under a shrub's skirt or in the low crown of a tree, and is not ground
  /// (0 returns = test off). Ground running on under a hedge lies at the ground level and stays
  /// ground.
  int under_veg_min_returns = 12;
  double under_veg_radius_m = 0.3;
  double under_veg_raised_m = 0.05;
  double under_veg_above_plane_m = 0.0;
  double under_veg_top_m = 0.6;
  double under_veg_ground_cell_m = 1.0;
};

struct GroundConfig {
  GroundMethod method = GroundMethod::kRobust;
  RobustGroundConfig robust;
  LevellingConfig levelling;  ///< before the robust ground
  GridGroundConfig grid;
  Seed000GroundConfig seed000;
  Seed002GroundConfig seed002;
};

struct GroundResult {
  std::vector<std::uint8_t> is_ground;  ///< 1 per input point that is ground, else 0
  double sensor_height_m = 0.0;         ///< height of the sensor above the ground near it
  std::size_t ground_count = 0;
  /// Tilt of the sensor from the up direction (deg) found by the levelling, and whether the
  /// cloud was levelled before the robust ground (tilt above LevellingConfig::level_tolerance_deg).
  double tilt_deg = 0.0;
  bool levelled = false;
  /// False when the levelling found no ground plane below the sensor within
  /// LevellingConfig::max_tilt_deg of its z axis, upright or turned over (a sensor tilted
  /// further, or not a sweep from above the ground): the cloud was segmented as if level.
  bool up_found = true;
  bool upside_down = false;  ///< the ground was found above the sensor: levelled turned over
};

/// The up direction of a sweep in its lidar frame.
struct UpEstimate {
  Eigen::Vector3d up{0, 0, 1};   ///< unit
  double tilt_deg = 0.0;         ///< angle between up and the lidar's z axis
  double sensor_height_m = 0.0;  ///< above the ground plane found (estimate only)
  std::size_t support = 0;       ///< lowest returns on the plane (estimate only)
  bool found = false;            ///< false: too few low returns, up stays z
  /// Found only with the sweep turned over (no ground below the sensor, a ground plane above
  /// it): up points down the lidar's z axis.
  bool upside_down = false;
};

/// The normal of the dominant ground plane below the sensor: RANSAC over the lowest return of
/// each cell of a coarse polar grid nearer than near_range_m, planes within max_tilt_deg of z
/// with the sensor above them, scored by their inliers less the returns well below them (the
/// ground is the lowest large plane), then refined by least squares on the inliers. When none
/// is found, the same with the sweep turned over: a sensor mounted upside down.
UpEstimate estimate_up(const PointCloud& cloud, const LevellingConfig& config = {});

/// The rotation taking `up` onto z that keeps the lidar's heading (its x axis laid level stays
/// the levelled x; for a pure pitch or roll the smallest rotation): lidar frame -> levelled frame.
Eigen::Matrix3d level_rotation(const UpEstimate& up);

/// The robust ground after levelling (LevellingConfig): what segment_ground runs for kRobust.
GroundResult ground_robust_levelled(const PointCloud& cloud, const SensorModel& sensor,
                                    const RobustGroundConfig& robust,
                                    const LevellingConfig& levelling);

/// Throws fieldlidar::Error for a cloud of implausible_span(), or one whose grid would exceed
/// GridGroundConfig::max_cells.
GroundResult ground_grid(const PointCloud& cloud, const GridGroundConfig& config = {});

/// Whether a cloud can be one sweep of a sensor at its origin (the robust ground assumes it).
struct SweepCheck {
  bool sweep = false;
  std::string reason;  ///< why (e.g. "ring field", "no return within 2 m below the origin")
};
/// A ring field or an organised layout is a sweep. Otherwise the points must surround the origin
/// (returns in at least half of 16 azimuth sectors) and the origin must sit above the ground
/// near it (the lowest returns 2-20 m out lie 0.1-10 m below it).
SweepCheck check_sweep(const PointCloud& cloud);

/// Largest span (m, along x, y or z) of a cloud the ground methods take: more is no scene but
/// coordinates in another unit than metres, or stray far points.
inline constexpr double kMaxSceneSpanM = 1e6;
/// Why `cloud` is no scene to segment when its valid points span more than kMaxSceneSpanM
/// ("the points span 2e+30 x 1e+30 x 3 m, more than 1e+06 m: ..."); nullopt when it is one.
std::optional<std::string> implausible_span(const PointCloud& cloud);
/// The same from the valid points' bounds (compute_bounds), when the caller has them.
std::optional<std::string> implausible_span(const Bounds3& bounds);

/// Ground flags for every point of `cloud` (invalid points are never ground). Throws
/// fieldlidar::Error for a cloud of implausible_span().
GroundResult segment_ground(const PointCloud& cloud, const SensorModel& sensor,
                            const GroundConfig& config = {});

GroundResult ground_robust(const PointCloud& cloud, const SensorModel& sensor,
                           const RobustGroundConfig& config = {});
GroundResult ground_seed000(const PointCloud& cloud, const SensorModel& sensor,
                            const Seed000GroundConfig& config = {});
/// Seed 000 on an image already built for the cloud.
GroundResult ground_seed000(const PointCloud& cloud, const RangeImage& image,
                            const Seed000GroundConfig& config = {});
GroundResult ground_seed002(const PointCloud& cloud, const SensorModel& sensor,
                            const Seed002GroundConfig& config = {});

/// Height of the sensor above the ground around it (m), from the lowest returns of the cells
/// nearer than `near_range_m`; `fallback_m` when the cloud has too few of them.
double estimate_sensor_height(const PointCloud& cloud, double near_range_m = 12.0,
                              double fallback_m = 0.0);

}  // namespace fieldlidar::segmentation
