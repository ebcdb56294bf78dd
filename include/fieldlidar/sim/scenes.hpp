#pragma once
/// \file The four procedural field scenes. The same config and seed always give the same scene.

#include <cstdint>

#include "fieldlidar/sim/scene.hpp"

namespace fieldlidar::sim {

/// A garden lawn (seed 000): gentle undulation, a kerb around it, a shed, a hedge, and the
/// operator walking the lawn's outline (straight edges, a right-angle corner, a curved edge).
/// Lawn interior is [0, length] x [0, width] (m) with the far edge (y = width) curved outwards.
struct LawnConfig {
  double length_m = 24.0;
  double width_m = 14.0;
  double undulation_m = 0.08;  ///< amplitude of the gentle ground waves
  /// Amplitude of short bumps (tussocks, ruts; 2-4 m wavelengths, slopes up to ~8 deg at
  /// 0.06 m) over the whole scene (m; 0 = a mown lawn).
  double roughness_m = 0.0;
  double edge_inset_m = 1.0;        ///< the operator walks this far inside the lawn edge
  double operator_speed_m_s = 1.0;  ///< 0.5 .. 1.5 normal walking
  double operator_start_m = 3.0;    ///< operator's start, arc length ahead of the robot's start
  // Scenario options (each off by default):
  bool second_person_crossing = false;  ///< a second person crosses ~2 m ahead of the operator
  double crossing_time_s = 10.0;        ///< when the crosser passes the operator's path
  bool operator_stops = false;          ///< the operator stands still for a while
  double stop_time_s = 8.0;
  double stop_duration_s = 5.0;
  bool operator_too_fast = false;  ///< the operator speeds up beyond what a mower follows
  double fast_time_s = 6.0;
  double fast_duration_s = 6.0;
  double fast_speed_m_s = 2.4;
  bool operator_behind_shed = false;  ///< the operator's path detours behind the shed
  /// The operator stands still for `wait_at_start_s` before walking off (the target is chosen
  /// while they stand).
  bool operator_waits_at_start = false;
  double wait_at_start_s = 5.0;
  /// Two leg-thick garden posts 0.25 m apart (a pair a leg detector can take for a person)
  /// beside the operator's start: `posts_ahead_m` along the path from its start and
  /// `posts_right_m` to its right (outwards, so they hide the operator from no point of the lap),
  /// nearer to the mower than the operator.
  bool posts_near_start = false;
  double posts_ahead_m = 1.4;
  double posts_right_m = 0.7;
  int extra_walkers = 0;  ///< people strolling at random across the garden
};
Scene make_lawn_scene(const LawnConfig& config = {}, std::uint64_t seed = 0);

/// A greenhouse (seed 002): concrete floor, walls, posts, roof trusses, rows of benches or raised
/// beds with plants, narrow aisles. The robot drives up one aisle and down the next.
struct GreenhouseConfig {
  double length_m = 30.0;
  int rows = 4;  ///< bench rows
  double bench_width_m = 1.6;
  double aisle_width_m = 1.0;  ///< narrow aisles
  double wall_height_m = 3.0;
  double post_spacing_m = 3.0;
  double plant_density_per_m2 = 6.0;
};
Scene make_greenhouse_scene(const GreenhouseConfig& config = {}, std::uint64_t seed = 0);

/// A forest stand (seed 003): uneven floor, trees of varied DBH, some leaning, forked or with low
/// branches, shrubs, crowns. A corridor along the robot's route is kept free of trunks.
struct ForestConfig {
  double size_x_m = 60.0;
  double size_y_m = 40.0;
  double trees_per_ha = 250.0;  ///< 50 .. 400
  double dbh_min_m = 0.10;
  double dbh_max_m = 0.80;
  double leaning_fraction = 0.15;
  double forked_fraction = 0.10;
  double low_branch_fraction = 0.3;
  double shrubs_per_ha = 300.0;
  double floor_relief_m = 1.0;  ///< amplitude of the floor's undulation
  double corridor_half_width_m = 1.8;
};
Scene make_forest_scene(const ForestConfig& config = {}, std::uint64_t seed = 0);

/// Off-road terrain (seed 004): hills with slopes up to max_slope_deg, a ditch, pits, a step,
/// rocks, bushes and overhanging branches on a heightfield.
struct TerrainConfig {
  double size_x_m = 60.0;
  double size_y_m = 40.0;
  double resolution_m = 0.2;  ///< heightfield node spacing
  double max_slope_deg = 35.0;
  int rocks = 40;
  int bushes = 30;
  int pits = 4;
  int branches = 6;
};
Scene make_terrain_scene(const TerrainConfig& config = {}, std::uint64_t seed = 0);

/// The scene of a kind with default config.
Scene make_scene(SceneKind kind, std::uint64_t seed);

}  // namespace fieldlidar::sim
