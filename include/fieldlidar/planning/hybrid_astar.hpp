#pragma once
/// \file Seed 004, step f: Hybrid A* on the traversability map (f1-f4), with Reeds–Shepp shots
/// and conjugate-gradient smoothing (f42), and typed failures.

#include <memory>
#include <string>

#include "fieldlidar/core/grid2d.hpp"
#include "fieldlidar/planning/planning_map.hpp"
#include "fieldlidar/planning/pose2.hpp"
#include "fieldlidar/planning/smoothing.hpp"
#include "fieldlidar/terrain/traversability.hpp"

namespace fieldlidar::planning {

/// Search settings. The default minimum turning radius is the default robot's
/// (terrain::RobotConfig::min_turn_radius_m, 1.0 m for the seed's chassis; why there);
/// planner_config_for (planner_for_robot.hpp) takes another robot's. Smaller radii make the
/// search find tighter but less followable paths.
struct PlannerConfig {
  /// R_min; valid range [0.1, 100] m
  double min_turn_radius_m = terrain::RobotConfig{}.min_turn_radius_m;
  int heading_bins = 72;  ///< search lattice headings (5 deg)
  /// Side of the search lattice's cells (m): a node whose pose falls in the cell and heading bin
  /// of an expanded node is a duplicate. 0: the map's cells. The footprint and the cost are
  /// always read at the map's own resolution; a coarser lattice expands fewer nodes (the maze of
  /// tests/planning on 0.25 m cells: a third on a 0.5 m lattice, for a path 1 % longer), a finer
  /// one more. A lattice of more than 4e9 cells and heading bins is `invalid_input`.
  double lattice_cell_m = 0.0;
  /// Arc length of one motion primitive (m); 0: just over a lattice cell's diagonal, so a child
  /// always leaves its parent's cell.
  double step_m = 0.0;
  /// Cost of a metre driven: (1 + tau_weight * (1 - tau)) (low tau costs more; seed 004).
  double tau_weight = 2.0;
  double reverse_factor = 2.0;              ///< metres driven backwards cost this many times more
  double direction_change_penalty_m = 3.0;  ///< added per switch between forward and reverse
  double turn_factor = 1.05;                ///< metres on an arc cost this many times more
  /// Reeds–Shepp shots to the goal are tried from nodes closer than this (m, straight line).
  double shot_distance_m = 20.0;
  /// The Reeds–Shepp distance enters the heuristic within this range of the goal (m); beyond
  /// it the straight-line distance (a lower bound of it) stands in, to save the solver's time.
  double rs_heuristic_range_m = 10.0;
  /// The obstacle-aware heuristic runs on cells this many times larger (speed; never
  /// overestimates: a coarse cell is blocked only when all its cells are).
  int heuristic_downsample = 1;
  /// f = g + w h: 1 keeps the search near-optimal; above 1 it expands fewer nodes for paths at
  /// most w times costlier (weighted A*). 1.2 on the 147k-cell benchmark map: 149 instead of
  /// 3.7k expansions per median plan, cost +2.5 % median, +8.8 % at worst (bench_planning).
  double heuristic_weight = 1.2;
  /// A search still going after this many expansions goes on with `late_heuristic_weight` (its
  /// open list re-keyed). The slowest plans spend thousands of expansions near a goal whose
  /// heading a rock field makes hard to meet, finding no cheaper path: on the 147k-cell benchmark
  /// map, 500 takes the p95 from 14.5 to 8.5 ms with the same path costs (bench_planning).
  /// 0: never; a search at weight 1 (the lattice's optimum) is never hurried.
  int late_expansions = 500;
  double late_heuristic_weight = 1.5;
  double goal_xy_tolerance_m = 0.2;     ///< a node this close to the goal ...
  double goal_yaw_tolerance_rad = 0.1;  ///< ... and this well aligned ends the search
  int max_expansions = 200000;          ///< expansion budget
  double time_budget_ms = 1000.0;       ///< wall-clock budget of one plan (heuristic included)
  double path_resolution_m = 0.1;       ///< spacing of the returned path's samples
  /// Replace sub-paths of the searched path by cheaper obstacle-free Reeds–Shepp curves between
  /// its poses (at R_min, every sample checked), before smoothing: it takes the lattice's zigzag
  /// out (bench_planning: length vs OMPL RRT*).
  bool shortcut = true;
  bool smooth = true;
  MapReadConfig map;
  SmoothingConfig smoothing;
};

/// Why a plan failed (or did not), like nav2's planner exceptions.
enum class PlanStatus {
  kSuccess,
  kInvalidInput,      ///< NaN/inf pose, absurd turning radius, budget or lattice
  kStartOffMap,       ///< start outside the map
  kGoalOffMap,        ///< goal outside the map
  kStartInCollision,  ///< the footprint at the start touches a blocked cell
  kGoalInCollision,   ///< the footprint at the goal touches a blocked cell
  kMapUnknown,        ///< the map has no known cell
  kNoPath,            ///< the search space is exhausted: the goal cannot be reached
  kTimedOut,          ///< time budget used up
  kExpansionLimit,    ///< expansion budget used up
};

/// "success", "no_path", ... (stable names for files and logs).
const char* to_string(PlanStatus status);

struct PlanResult {
  PlanStatus status = PlanStatus::kNoPath;
  Path path;          ///< smoothed when smoothing is on; empty on failure
  Path raw_path;      ///< the search's path before shortcutting and smoothing
  double cost = 0.0;  ///< g of the goal (m-equivalent)
  int expansions = 0;
  bool late_weight = false;  ///< the search went on with late_heuristic_weight
  int shots_tried = 0;
  bool reached_by_shot = false;
  double heuristic_ms = 0.0;  ///< obstacle-aware Dijkstra (lazy) time
  double search_ms = 0.0;     ///< whole search, heuristic included
  double shortcut_ms = 0.0;   ///< Reeds–Shepp shortcutting of the searched path
  int shortcuts = 0;          ///< sub-paths it replaced
  double smooth_ms = 0.0;
  SmoothingReport smoothing;
  bool ok() const { return status == PlanStatus::kSuccess; }
};

/// The planner over one map; reuse it for many queries on the same map.
class HybridAStar {
 public:
  /// Builds the planning map (throws fieldlidar::Error as PlanningMap does).
  HybridAStar(const Grid2D& map, const terrain::RobotConfig& robot, PlannerConfig config = {});
  ~HybridAStar();
  HybridAStar(HybridAStar&&) noexcept;
  HybridAStar& operator=(HybridAStar&&) noexcept;

  PlanResult plan(const Pose2& start, const Pose2& goal);

  const PlanningMap& map() const { return map_; }
  const PlannerConfig& config() const { return config_; }

 private:
  struct Search;
  PlanningMap map_;
  PlannerConfig config_;
  std::unique_ptr<Search> search_;  ///< buffers reused between plans
};

/// One-shot convenience.
PlanResult plan_path(const Grid2D& map, const terrain::RobotConfig& robot, const Pose2& start,
                     const Pose2& goal, const PlannerConfig& config = {});

}  // namespace fieldlidar::planning
