#pragma once
/// \file Seed 004, steps b-d: the dynamic voxel grid, roughness and pits, and the layered
/// 2D+2.5D traversability map of one scan.

#include <cstdint>
#include <span>

#include "fieldlidar/core/grid2d.hpp"
#include "fieldlidar/core/point_cloud.hpp"
#include "fieldlidar/core/pose.hpp"
#include "fieldlidar/core/sensor_model.hpp"
#include "fieldlidar/segmentation/ground.hpp"

namespace fieldlidar::terrain {

/// The robot the map is made for (the seed's chassis by default).
struct RobotConfig {
  double length_m = 0.93;
  double width_m = 0.58;
  double max_slope_deg = 25.0;  ///< rho_max: steeper ground is a 2D obstacle
  double max_step_m = 0.20;     ///< h_max: larger steps or pits within a cell are impassable
  double clearance_m = 1.2;     ///< objects higher than this above the ground are overhangs
  double min_obstacle_height_m = 0.15;  ///< lower objects are driven over
  /// R_min, the tightest turn the planner may ask for (m). 1.0 m for the seed's 0.93 x 0.58 m
  /// four-wheel skid-steer chassis: turning about its centre (R = 0) scrubs all four tyres
  /// sideways, which on rough or soft ground digs in and slews the robot off its plan; at R = 1 m
  /// the inner wheels (0.29 m inside the centre line) still roll forward at 71 % of the outer
  /// wheels' speed, the lateral scrub of a 0.93 m long base stays small, and every U-turn fits
  /// in a 2 m (4-cell) wide lane of a 0.5 m map.
  double min_turn_radius_m = 1.0;
};

/// How the map is made. The voxel side g_l (formula (1) of the seed is lost) is the robot's
/// diagonal rounded up to an odd number of cells: the smallest square window, centred on a cell,
/// that holds the robot in any heading (0.93 x 0.58 m -> 1.10 m -> 3 cells of 0.5 m = 1.5 m).
/// Its height is g_h = g_l * tan(rho_max), from the lowest ground of the window up, so ground
/// up to rho_max fits in it and overhangs fall out.
struct TraversabilityConfig {
  RobotConfig robot;
  double cell_m = 0.5;          ///< sub-cell (map cell) side
  double max_range_m = 40.0;    ///< points farther from the sensor (horizontally) are left out
  double below_ground_m = 0.3;  ///< the voxel starts this far below its lowest ground point
  int min_voxel_points = 6;     ///< fewer points in a voxel: its cell stays unknown
  int min_cell_points = 2;      ///< a cell needs this many of its own points to be known
  int min_obstacle_points = 2;  ///< pass-through returns that make a cell a projected obstacle
  /// tau = clamp(1 - a * rho / rho_max - b * roughness / (h_max / 2), 0, 1) on passable cells,
  /// 0 on impassable ones; roughness is the mean |d_k| (m) of the cell's points to the voxel
  /// plane (the seed's r_sum = sum |d_k| is kept as its own layer).
  double weight_slope = 0.6;      ///< a
  double weight_roughness = 0.4;  ///< b
  /// The seed as written (steps b and c only): the 2D obstacle is the voxel's slope alone, no
  /// pass-through projection of obstacle points.
  bool project_obstacles = true;
  /// The slope layer from the plane of the voxel's ground returns (when it holds
  /// min_voxel_points of them) rather than of all its points (the seed's).
  bool ground_plane = true;
  /// The step of a cell is the height range of the whole voxel's returns about the plane (the
  /// robot's reach), rather than the cell's own returns (the seed's sub-cell).
  bool voxel_step = true;
  /// Returns that spread less than this (m, standard deviation) across their main direction lie
  /// along a line (one ring crossing the cell or window, its range noise along the beam): their
  /// plane's tilt across the line is not measured, and the least-tilted plane through the line
  /// stands for it (its slope the line's own; the ground segmentation keeps a 0.04 m line its
  /// own way). Plain PCA there returned the plane of the ring and the beam: a VLP-32C's lowest
  /// ring (-25 deg, alone out to 4.3 m) made level ground round the robot a 15-27 deg slope.
  /// Navigate pairs, seeds 2-21, 0 / 0.05 / 0.1: VLP-32C 166 / 172 / 170 of 184 arrive, 46 / 10
  /// / 10 drives over 1.15 x the truth plan; VLP-16 180 / 180 / 178, drives touching
  /// truth-impassable cells 13 / 10 / 11. 0: plain PCA (the seed's).
  double min_plane_spread_m = 0.05;
  segmentation::GroundConfig ground;
};

/// The seed's method as written.
TraversabilityConfig seed004_config();

/// Voxel side g_l (m) and height g_h (m) for a config; raises fieldlidar::Error on an absurd
/// robot (sizes not in (0, 20] m, slope not in (0, 80) deg, step not in (0, 5] m), cell side (not
/// in (0, 10] m) or line spread (min_plane_spread_m not in [0, 10] m): the map's constructors
/// and map_scan validate their config through it.
double voxel_side_m(const TraversabilityConfig& config);
double voxel_height_m(const TraversabilityConfig& config);

/// Layer names of the map (NaN = unknown in every layer but "points").
namespace layer {
inline constexpr const char* kNormalX = "normal_x";
inline constexpr const char* kNormalY = "normal_y";
inline constexpr const char* kNormalZ = "normal_z";
inline constexpr const char* kSlopeDeg = "slope_deg";
inline constexpr const char* kRoughness = "roughness_m";         ///< mean |d_k|
inline constexpr const char* kRoughnessSum = "roughness_sum_m";  ///< r_sum
inline constexpr const char* kStep = "step_m";                   ///< max d_k - min d_k
inline constexpr const char* kObstacle2d = "obstacle_2d";        ///< 1: voxel slope > rho_max
inline constexpr const char* kObstacleProjected = "obstacle_projected";  ///< claim 5
inline constexpr const char* kImpassable = "impassable";
inline constexpr const char* kTraversability = "traversability";  ///< tau in [0, 1]
inline constexpr const char* kElevation = "elevation_m";
inline constexpr const char* kPoints = "points";  ///< returns behind the cell (0 = unknown)
/// Fused map only: 1 on a likely negative obstacle not seen yet (a trench shadow,
/// negative_obstacle.hpp, whose traversability is still unknown), else 0.
inline constexpr const char* kNegativeObstacle = "negative_obstacle";
}  // namespace layer

/// The map from points already in the map frame (z up) with their ground flags, on `geometry`.
Grid2D build_layers(std::span<const Eigen::Vector3d> points_m,
                    std::span<const std::uint8_t> is_ground, const GridGeometry& geometry,
                    const TraversabilityConfig& config);

/// One scan: ground segmentation in the lidar frame, then the layers around the sensor in the
/// map frame given by T_map_lidar. Empty or all-invalid scans give an all-unknown map.
Grid2D map_scan(const PointCloud& scan, const SensorModel& sensor, const Pose& T_map_lidar,
                const TraversabilityConfig& config = {});

/// A whole area at once (airborne or terrestrial survey, LAS/PCD): grid ground, the cloud's own
/// frame (points relative to origin_m).
Grid2D map_area(const PointCloud& cloud, const TraversabilityConfig& config = {});

}  // namespace fieldlidar::terrain
