#pragma once
// The obstacle-aware half of the Hybrid A* heuristic: cost-to-goal of a point robot over the
// grid (8-connected Dijkstra from the goal cell over unblocked cells, each metre costing
// 1 + tau_weight * (1 - tau)), computed lazily: a query settles cells only until its own is.
// It runs on cells `downsample` times larger (as nav2's Smac planner does): a coarse cell is
// blocked only when all its cells are and costs the least of theirs, so it never overestimates.

#include <chrono>
#include <cstdint>
#include <queue>
#include <utility>
#include <vector>

#include "fieldlidar/planning/planning_map.hpp"

namespace fieldlidar::planning {

class ObstacleHeuristic {
 public:
  /// Starts a new search from `goal_cell` (a linear index of an unblocked cell).
  void reset(const PlanningMap& map, long goal_cell, double tau_weight, int downsample);
  /// Cost (m-equivalent) from the cell (of the planning map) to the goal; +inf when the goal
  /// cannot be reached, NaN when `deadline` passed before the cell was settled.
  double cost_m(long cell, std::chrono::steady_clock::time_point deadline);
  std::size_t settled() const { return settled_count_; }

 private:
  using Entry = std::pair<float, std::uint32_t>;
  long coarse_of(long cell) const;
  const PlanningMap* map_ = nullptr;
  double tau_weight_ = 0.0;
  int factor_ = 1, cw_ = 0, ch_ = 0;
  double coarse_res_m_ = 0.0;
  std::vector<float> mult_;            ///< cost per metre of each coarse cell
  std::vector<std::uint8_t> blocked_;  ///< coarse cells
  std::vector<float> dist_;
  std::vector<std::uint8_t> settled_;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open_;
  std::size_t settled_count_ = 0;
};

}  // namespace fieldlidar::planning
