#pragma once
// The obstacle-aware half of the Hybrid A* heuristic: cost-to-goal of the robot's centre over the
// grid (8-connected Dijkstra from the goal cell, each metre costing 1 + tau_weight * (1 - tau)),
// computed lazily: a query settles cells only until its own is. The cells are settled in the
// order of an A* search from the goal towards a focus cell (the start: Silver's reverse
// resumable A*, with the octile distance to the focus at the cheapest cost per metre as its
// consistent heuristic), so a query near the line from the goal to the start settles few cells;
// each settled cell's cost is exact, whatever the order. A cell counts as blocked when
// no point of it can hold the robot's centre: every point lies closer than the footprint's
// inscribed radius (half its width plus the margin) to a blocked cell, so a gap too narrow for
// the footprint is closed to the heuristic too and a goal behind it fails at once; no pose the
// search can take lies in such a cell, so the heuristic stays a lower bound.
// It runs on cells `downsample` times larger (as nav2's Smac planner does): a coarse cell is
// blocked only when all its cells are and costs the least of theirs, so it never overestimates.

#include <chrono>
#include <cstdint>
#include <vector>

#include "fieldlidar/planning/planning_map.hpp"

namespace fieldlidar::planning {

/// Per cell of `map`: 1 when every point of the cell is closer than `radius_m` to a blocked
/// cell (or is blocked itself), so the footprint's inscribed disc cannot be centred in it.
std::vector<std::uint8_t> centre_blocked_cells(const PlanningMap& map, double radius_m);

class ObstacleHeuristic {
 public:
  /// Starts a new search from `goal_cell` (a linear index of an unblocked cell), settling cells
  /// towards `focus_cell` first (-1: in order of cost alone, Dijkstra's).
  void reset(const PlanningMap& map, long goal_cell, long focus_cell, double tau_weight,
             int downsample);
  /// Cost (m-equivalent) from the cell (of the planning map) to the goal; +inf when the goal
  /// cannot be reached, NaN when `deadline` passed before the cell was settled.
  double cost_m(long cell, std::chrono::steady_clock::time_point deadline);
  std::size_t settled() const { return settled_count_; }

 private:
  long coarse_of(long cell) const;  ///< index in the padded coarse grid
  void push(float key_m, std::uint32_t i);
  float focus_distance(long x, long y) const;  ///< A* heuristic: lower bound of cost to focus
  const PlanningMap* map_ = nullptr;
  double tau_weight_ = 0.0;
  int factor_ = 1, cw_ = 0, ch_ = 0, pw_ = 0;  ///< coarse size; pw_: padded row length
  double coarse_res_m_ = 0.0;
  float min_mult_ = 1.0f;             ///< least cost per metre of any unblocked cell
  long focus_x_ = -1, focus_y_ = -1;  ///< focus cell in the padded grid; -1: none
  // Padded coarse grid (a blocked border of one cell: no bounds checks in the inner loop).
  std::vector<float> half_mult_;       ///< half the cost per metre of each cell
  std::vector<std::uint8_t> blocked_;  ///< static per map
  std::vector<std::uint8_t> closed_;   ///< blocked or settled
  std::vector<float> dist_;
  /// Radix heap of (key bits << 32 | cell), key = cost + focus_distance: the search pops keys
  /// in increasing order (the heuristic is consistent; rounding is clamped), so
  /// bucket b holds the keys whose highest bit differing from the last popped key is b - 1.
  std::vector<std::uint64_t> buckets_[33];
  std::uint32_t last_key_ = 0;
  std::size_t queued_ = 0;
  bool pop(std::uint32_t* cell);
  std::size_t settled_count_ = 0;
};

}  // namespace fieldlidar::planning
