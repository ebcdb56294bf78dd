#pragma once
/// \file The traversability map fused over time (issue 16, item 3): scans placed by the robot's
/// poses update per-cell sufficient statistics, and only the cells a scan touched (and the cells
/// whose voxel window holds them) get their layers recomputed. A rolling local map around the
/// robot and the global map of the whole drive are views of the same cells.

#include <cstdint>
#include <limits>
#include <memory>
#include <span>

#include "fieldlidar/core/grid2d.hpp"
#include "fieldlidar/core/point_cloud.hpp"
#include "fieldlidar/core/pose.hpp"
#include "fieldlidar/core/sensor_model.hpp"
#include "fieldlidar/terrain/negative_obstacle.hpp"
#include "fieldlidar/terrain/traversability.hpp"

namespace fieldlidar::terrain {

/// How scans are fused. The layers use `layers` (robot, cell, range, ground segmentation,
/// weights a and b of tau).
///
/// Per cell the map keeps the count, sum and sum of squares of its ground returns (relative to
/// the cell's centre), so the plane of a voxel window is the sum of its cells' statistics: a cell
/// seen from several places gets more returns and a better plane. Obstacles are evidence in
/// log-odds: a scan with `min_obstacle_points` returns between the robot's min_obstacle_height and
/// clearance above the cell's ground adds `hit_log_odds`; a scan that sees
/// `min_free_ground_points` ground returns in the cell and no such return adds `miss_log_odds`
/// (negative), and so does a scan whose ray crosses the cell between min_obstacle_height and the
/// cell's obstacle top without ending there (seen through), so a person who walked through leaves
/// no obstacle once the ground there is seen again or seen past. A scan that hits the cell wins
/// over one that sees through it. A cell is an obstacle while its log-odds is above 0.
///
/// The evidence is per time, not per scan: consecutive sweeps of a 10 Hz sensor see nearly the
/// same thing from nearly the same place, and counted whole they let the last half second decide
/// a cell (every sweep of seed 23's first 30 s: impassable recall 0.961 counted whole, 0.968 per
/// time; walkers crossing seed 21's drive left 5 ghost cells, now none).
struct FusionConfig {
  TraversabilityConfig layers;
  double local_side_m = 40.0;  ///< side of the rolling local map around the last sensor position
  float hit_log_odds = 0.85f;
  float miss_log_odds = -0.7f;
  float min_log_odds = -2.0f;
  float max_log_odds = 3.5f;
  /// hit_log_odds and miss_log_odds are for scans this far apart (s): a scan stamped dt after
  /// the previous one adds min(1, dt / evidence_period_s) of them. Scans without increasing
  /// stamps (and evidence_period_s = 0) count whole.
  double evidence_period_s = 0.5;
  int min_free_ground_points = 3;
  /// Every n-th return's ray is traced for see-through evidence (0: none).
  int see_through_stride = 4;
  /// A non-ground return's height is taken above the cell's ground plane under it, once earlier
  /// scans gave the cell one; else (and when false) above this scan's lowest ground return in the
  /// cell. On a slope that is the cell's low corner: harmless on 0.5 m cells (the drives score
  /// the same or slightly better without the plane), but a survey's 3-5 m cells would lift low
  /// plants into the robot's body (map_area_fused sets it).
  bool obstacle_height_from_plane = false;
  /// And never below the plane of this scan's ground returns in the 3 x 3 cells around the
  /// return (min_voxel_points of them, not along one line, no steeper than max_slope_deg) under
  /// it: on a hill's flank a return in the upper half of a 0.5 m cell stood more than
  /// min_obstacle_height above the lowest ground there by the slope alone (seeds 0 and 1, the
  /// hill within 13 m: 67 and 99 truth-passable cells with obstacle evidence, 47 and 65 with the
  /// plane; their halos 158 and 148 -> 138 and 107 cells).
  bool obstacle_height_from_scan_plane = true;
  /// Non-ground returns more than the robot's max step below the cell's ground (a pit's or
  /// ditch's wall seen over its rim) are obstacle evidence too.
  bool pit_evidence = true;
  /// A cell is called passable only when every cell of its voxel window (the robot's footprint)
  /// was seen; else it stays unknown (a shadow behind a rock or inside a pit is no free ground).
  bool passable_needs_full_window = true;
  /// But for up to this many cells of the window that no return hit, each bridged by the ground
  /// model: the two cells either side of it on a line inside the window are seen ground within
  /// max_step of each other, and no cell of the window next to it holds obstacle evidence (the
  /// gaps between a sweep's rings at range; the bridged cell itself stays unknown).
  int max_bridged_cells = 2;
  /// A gap is bridged only while the two cells either side hold at most this many ground returns
  /// together: a cell still unseen beside well-seen ones is a shadow (a cliff's foot, behind a
  /// rim), not the space between two rings.
  int bridge_max_ground_points = 60;
  /// An obstacle's 4 neighbour cells are impassable too (its footprint is larger than the
  /// returns on it show: the low rim of a rock, the far side of a bush), when the cells are
  /// smaller than the robot (a voxel window of more than one cell): a cell larger than the robot
  /// holds that rim itself.
  bool obstacle_halo = true;
  /// A low rock or mound the ground segmentation kept as ground is an obstacle: a cell whose
  /// ground top stands above both neighbours on a line through it (the better of the four lines;
  /// a step, higher on one side only, is judged by max_step instead) by more than the robot's
  /// min_obstacle_height less bump_margin_m. The ground top, about the voxel window's plane, is
  /// the larger of the cell's mean plus bump_sigmas standard deviations and its second-highest
  /// ground return (from scans that saw nothing raised in the cell, less the plane's rise over
  /// half the cell's diagonal); the neighbours are their mean ground.
  bool bump_obstacles = true;
  double bump_sigmas = 2.0;
  /// The measured top is low by the rock's rounded cap and the neighbours' share of it.
  double bump_margin_m = 0.03;
  /// The planes give the mean slope over a cell or window, the robot tips on the steepest part:
  /// ground steeper than max_slope_deg - slope_margin_deg is a 2D obstacle.
  double slope_margin_deg = 3.0;
  /// The steepest rise between a cell's mean ground and a neighbour's (a wall, a pit's rim, a
  /// ditch's edge sharper than the planes show) is a 2D obstacle above max_slope_deg less this.
  /// It measures the steep part itself, so it takes no plane margin: with 3 deg, one noisy pair
  /// of the eight neighbours on a hill's 21-24 deg flank (truth passable to 25 deg) blocked the
  /// cell (seeds 0 and 1, the hill within 13 m, the sweeps of three drives each: 203 and 218
  /// truth-passable cells blocked as too steep, 134 and 142 with 0; none truth-impassable let
  /// through either way).
  double edge_slope_margin_deg = 0.0;
  /// The slope layer of a passable cell is the steeper of its own plane and its voxel window's
  /// (the truth is the steepest ground in the cell, both planes are means) rather than the one
  /// whose normal it keeps. Seeds 21-25, scans every 0.5 s: slope RMSE on truth-passable cells
  /// 1.13/1.39/1.01/1.15/1.25 -> 1.06/1.19/0.87/1.06/1.07 deg.
  bool slope_from_steeper_plane = true;
  int min_ground_points = 3;  ///< fused ground returns of its own for a cell to be known
  /// A cell's own plane gives its slope once it holds this many ground returns (else the voxel
  /// window's plane does).
  int min_own_plane_points = 40;
  /// The slope layer of an impassable cell is the plane of the ground returns around it that
  /// hold no obstacle (cells with obstacle evidence, bumps or returns steeper than max_slope_deg
  /// left out; when too few are left, only the steep ones; NaN when still too few) rather than
  /// its own plane, which takes in a rock's foot
  /// the ground segmentation kept: the ground's slope, not the rock's. The classification is
  /// the same either way.
  bool blocked_slope_from_clear_ground = true;
  /// The step over the voxel window: range of the cells' mean offsets from the plane, each widened
  /// by this many standard deviations of its returns about the plane.
  double step_sigmas = 1.0;
  /// Trench shadows (negative_obstacle.hpp): the cells under a sunk beam are marked, and shown
  /// in layer kNegativeObstacle while their traversability is unknown (a traversability since,
  /// passable or not, overrides the mark); a later scan's level ground in a cell clears it. The
  /// other layers do not use it.
  NegativeObstacleConfig negative_obstacles = {};
};

/// What one scan did to the map.
struct FusionUpdate {
  std::size_t points = 0;         ///< valid returns within range
  std::size_t ground_points = 0;  ///< of which ground
  std::size_t cells_touched = 0;  ///< cells holding one of its returns
  std::size_t cells_updated = 0;  ///< cells whose layers were recomputed
};

class TerrainMap {
 public:
  /// Raises fieldlidar::Error on an absurd robot or config.
  explicit TerrainMap(FusionConfig config = {});
  ~TerrainMap();
  TerrainMap(TerrainMap&&) noexcept;
  TerrainMap& operator=(TerrainMap&&) noexcept;

  /// One scan in its lidar frame at pose T_map_lidar, stamped scan.stamp_s: ground segmentation,
  /// then add_points. Empty or all-invalid scans change nothing.
  FusionUpdate add_scan(const PointCloud& scan, const SensorModel& sensor, const Pose& T_map_lidar);
  /// Returns already in the map frame (z up) with their ground flags, seen from sensor_m at
  /// stamp_s (s; NaN: unknown, the scan's evidence counts whole). Non-finite points are skipped.
  FusionUpdate add_points(std::span<const Eigen::Vector3d> points_m,
                          std::span<const std::uint8_t> is_ground, const Eigen::Vector3d& sensor_m,
                          double stamp_s = std::numeric_limits<double>::quiet_NaN());

  /// The layers (names of terrain::layer, NaN = unknown) on a square of side side_m centred on
  /// center_m, cells on multiples of the cell side.
  Grid2D local_map(const Eigen::Vector2d& center_m, double side_m) const;
  /// The rolling local map: local_side_m around the last scan's sensor.
  Grid2D local_map() const;
  /// Every cell seen so far (an empty grid before the first scan).
  Grid2D global_map() const;

  std::size_t scans() const;
  const FusionConfig& config() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// A whole surveyed area (airborne or terrestrial, LAS/PCD) through the fused map's cells: grid
/// ground segmentation, then every valid return added at once, in the cloud's own frame (points
/// relative to origin_m). A survey has no sensor position, so no ray is traced (no see-through
/// evidence), and a cell's own plane gives its slope from `survey_own_plane_points` ground returns
/// (a survey holds few per cell). `is_water` (empty, or one flag per point, e.g. LAS class 9):
/// water returns are never ground, and a cell holding min_obstacle_points of them is impassable
/// (a lake is flat, and would otherwise look like the best ground of the area). Raises
/// fieldlidar::Error on an absurd robot or config, or flags that do not match the points.
inline constexpr int survey_own_plane_points = 5;
Grid2D map_area_fused(const PointCloud& cloud, const FusionConfig& config = {},
                      std::span<const std::uint8_t> is_water = {});

}  // namespace fieldlidar::terrain
