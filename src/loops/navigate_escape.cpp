// The navigate loop's way out of a start the planner calls in collision: the shortest straight
// or R_min arc that the step check allows and that ends on a pose the planner calls free.

#include <algorithm>
#include <cmath>

#include "fieldlidar/loops/navigate_maps.hpp"
#include "fieldlidar/planning/path_follower.hpp"

namespace fieldlidar::loops {

bool footprint_enters_blocked(const GridGeometry& area, const std::vector<std::uint8_t>& blocked,
                              const std::vector<long>& standing, const planning::Pose2& next,
                              const terrain::RobotConfig& robot) {
  auto stands_on = [&](long c) {
    return std::find(standing.begin(), standing.end(), c) != standing.end();
  };
  for (long c : footprint_cells(area, next, robot)) {
    if (c < 0) return !stands_on(c);
    if (blocked[std::size_t(c)] && !stands_on(c)) return true;
  }
  return false;
}

std::optional<planning::Path> escape_path(const planning::PlanningMap& map,
                                          const std::vector<std::uint8_t>& blocked,
                                          const planning::Pose2& from, bool goal_behind,
                                          double max_m, double step_m) {
  const GridGeometry& area = map.geometry();
  const terrain::RobotConfig& robot = map.robot();
  const auto standing = footprint_cells(area, from, robot);
  // Straight first (towards the goal's side first), then the four arcs at R_min.
  const double k = 1.0 / robot.min_turn_radius_m;
  struct Move {
    double dir, curvature;
  };
  const double first = goal_behind ? -1.0 : 1.0;
  const Move moves[] = {{first, 0.0}, {-first, 0.0}, {first, k},
                        {first, -k},  {-first, k},   {-first, -k}};
  const int n = std::max(1, int(std::floor(max_m / step_m + 1e-9)));
  std::vector<planning::Path> paths(std::size(moves), planning::Path{{from, false}});
  std::vector<bool> open(std::size(moves), true);
  for (int i = 1; i <= n; ++i)
    for (std::size_t m = 0; m < std::size(moves); ++m) {
      if (!open[m]) continue;
      const planning::Pose2 p = planning::integrate_unicycle(
          from, moves[m].dir, moves[m].dir * moves[m].curvature, step_m * i);
      if (footprint_enters_blocked(area, blocked, standing, p, robot)) {
        open[m] = false;
        continue;
      }
      paths[m].push_back({p, moves[m].dir < 0});
      if (map.pose_free(p)) return paths[m];
    }
  return std::nullopt;
}

}  // namespace fieldlidar::loops
