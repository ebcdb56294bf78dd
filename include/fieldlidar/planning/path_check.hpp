#pragma once
/// \file A planned path checked against a newer map: is any of its remaining poses now blocked,
/// and what does the rest of it cost there. What a closed loop needs to decide when to re-plan.

#include <cstddef>
#include <optional>
#include <vector>

#include "fieldlidar/planning/pose2.hpp"

namespace fieldlidar::planning {

class PlanningMap;

/// The first sample at or after `from` whose footprint is not free on `map` (PlanningMap::
/// pose_free: the planner's own inflated check), nullopt when the rest of the path is free.
std::optional<std::size_t> first_blocked_sample(const PlanningMap& map, const Path& path,
                                                std::size_t from = 0);

/// The planner's cost (m-equivalent) of each step of the path on `map`: element i is the cost of
/// driving from sample i-1 to sample i (element 0 is 0): the step's length times
/// (1 + tau_weight * (1 - tau)) at the cell it ends in (tau 0 off the map), times reverse_factor
/// when driven backwards. Direction-change penalties are left out: they do not depend on the
/// map. The cost of the rest of the path from sample k is the sum of the elements after k.
std::vector<double> path_step_costs(const PlanningMap& map, const Path& path, double tau_weight,
                                    double reverse_factor);

}  // namespace fieldlidar::planning
