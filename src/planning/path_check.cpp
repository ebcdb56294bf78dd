// A path against a newer map: the first blocked sample and the cost of the rest (re-planning
// triggers of a closed loop).

#include "fieldlidar/planning/path_check.hpp"

#include <cmath>

#include "fieldlidar/planning/planning_map.hpp"

namespace fieldlidar::planning {

std::optional<std::size_t> first_blocked_sample(const PlanningMap& map, const Path& path,
                                                std::size_t from) {
  for (std::size_t i = from; i < path.size(); ++i)
    if (!map.pose_free(path[i].pose)) return i;
  return std::nullopt;
}

std::vector<double> path_step_costs(const PlanningMap& map, const Path& path, double tau_weight,
                                    double reverse_factor) {
  std::vector<double> cost(path.size(), 0.0);
  for (std::size_t i = 1; i < path.size(); ++i) {
    const Pose2& a = path[i - 1].pose;
    const Pose2& b = path[i].pose;
    const long c = map.cell_index(b.x_m, b.y_m);
    const double tau = c < 0 ? 0.0 : map.tau(std::size_t(c));
    const double step = std::hypot(b.x_m - a.x_m, b.y_m - a.y_m) * (1.0 + tau_weight * (1.0 - tau));
    cost[i] = path[i].reverse ? reverse_factor * step : step;
  }
  return cost;
}

}  // namespace fieldlidar::planning
