#pragma once
// The cost the search minimises, per sampled step of a path: metres driven times
// (1 + tau_weight (1 - tau)) at the step's end cell, times reverse_factor backwards and
// turn_factor on a bend, plus direction_change_penalty_m per switch of direction. Shared by the
// search's Reeds–Shepp shots and the shortcutting of its path, so both compare like with like.

#include <cmath>

#include "fieldlidar/planning/planning_map.hpp"
#include "fieldlidar/planning/pose2.hpp"

namespace fieldlidar::planning {

struct PathCostTerms {
  double tau_weight = 2.0;
  double reverse_factor = 2.0;
  double turn_factor = 1.05;
  double direction_change_penalty_m = 3.0;
};

/// Cost of the step from sample a to sample b (b.reverse: driven backwards); no penalty term.
inline double step_cost(const PlanningMap& map, const PathCostTerms& c, const PathPose& a,
                        const PathPose& b) {
  const long cell = map.cell_index(b.pose.x_m, b.pose.y_m);
  const double tau = cell < 0 ? 0.0 : map.tau(std::size_t(cell));
  const bool turning = std::abs(wrap_angle(b.pose.yaw_rad - a.pose.yaw_rad)) > 1e-9;
  return std::hypot(b.pose.x_m - a.pose.x_m, b.pose.y_m - a.pose.y_m) *
         (1.0 + c.tau_weight * (1.0 - tau)) * (b.reverse ? c.reverse_factor : 1.0) *
         (turning ? c.turn_factor : 1.0);
}

}  // namespace fieldlidar::planning
