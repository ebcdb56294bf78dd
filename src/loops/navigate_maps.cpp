// The navigate loop's maps: the truth read as a planner map, the fused map on the operating area,
// footprints on either.

#include "fieldlidar/loops/navigate_maps.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "fieldlidar/planning/planning_map.hpp"

namespace fieldlidar::loops {

namespace L = terrain::layer;

Grid2D truth_planning_grid(const Grid2D& truth, const terrain::TraversabilityConfig& layers) {
  Grid2D out(truth.geometry());
  auto tau = out.add_layer(L::kTraversability, 0.f);
  const auto passable = truth.layer("passable");
  const auto slope = truth.layer("slope_deg");
  for (std::size_t i = 0; i < tau.size(); ++i)
    if (passable[i] > 0.5f)
      tau[i] = float(
          std::clamp(1.0 - layers.weight_slope * slope[i] / layers.robot.max_slope_deg, 0.01, 1.0));
  return out;
}

double blind_range_m(const AreaGridRules& rules, const Eigen::Vector2d& u) {
  if (!(rules.blind_radius_m > 0) || !(rules.sensor_height_m > 0)) return 0.0;
  // The lowest beam's angle below the robot's ground plane in direction u: the level mount's,
  // plus how far the sensor's z axis leans towards u from the plane's normal.
  const auto lean = [&](const Eigen::Vector3d& a) { return std::atan2(a.head<2>().dot(u), a.z()); };
  const double down = std::atan2(rules.sensor_height_m, rules.blind_radius_m) +
                      lean(rules.sensor_up) - lean(rules.ground_normal);
  if (!(down > 1e-3)) return std::numeric_limits<double>::infinity();
  return rules.sensor_height_m / std::tan(down);
}

Grid2D area_grid(const terrain::TerrainMap& map, const GridGeometry& area,
                 const AreaGridRules& rules) {
  std::vector<std::uint8_t> drop_marks;
  return area_grid(map, area, rules, drop_marks);
}

Grid2D area_grid(const terrain::TerrainMap& map, const GridGeometry& area,
                 const AreaGridRules& rules, std::vector<std::uint8_t>& drop_marks) {
  Grid2D out(area);
  auto tau = out.add_layer(L::kTraversability, NAN);
  auto imp = out.add_layer(L::kImpassable, NAN);
  auto pts = out.add_layer(L::kPoints, 0.f);
  const Grid2D global = map.global_map();
  if (global.geometry().cell_count() == 0) return out;
  const auto gtau = global.layer(L::kTraversability);
  const auto gimp = global.layer(L::kImpassable);
  const auto gpts = global.layer(L::kPoints);
  const auto gelev = global.layer(L::kElevation);
  const auto gneg = global.layer(L::kNegativeObstacle);
  const GridGeometry& g = global.geometry();
  std::vector<float> elevation(area.cell_count(), NAN);  // NaN: no ground plane
  // A guess from a shadow never makes a goal unreachable.
  const auto off_goal = [&](int ix, int iy) {
    return (area.cell_center(ix, iy) - rules.goal_xy_m).norm() > rules.goal_clear_m;
  };
  const auto in_blind_range = [&](const Eigen::Vector2d& p) {
    const Eigen::Vector2d v = p - rules.sensor_xy_m;
    const double d = v.norm();
    return d < 1e-9 || d < blind_range_m(rules, v / d);
  };
  for (int iy = 0; iy < area.height; ++iy)
    for (int ix = 0; ix < area.width; ++ix) {
      const auto c = g.cell_of(area.cell_center(ix, iy));
      if (!c) continue;
      const std::size_t j = g.linear_index(c->x(), c->y()), i = area.linear_index(ix, iy);
      tau[i] = gtau[j];
      imp[i] = gimp[j];
      pts[i] = gpts[j];
      elevation[i] = gelev[j];
      if (rules.negative_impassable && gneg[j] > 0.5f && off_goal(ix, iy)) imp[i] = 1.f;
      if (!std::isfinite(elevation[i]) && !std::isfinite(tau[i]) &&
          pts[i] >= float(rules.blind_points) && in_blind_range(area.cell_center(ix, iy)))
        imp[i] = 1.f;
    }
  drop_marks.resize(area.cell_count(), 0);
  mark_drop_bands(area, elevation, pts, known_blocked(out), rules, drop_marks);
  mark_blind_drops(area, elevation, pts, rules, drop_marks);
  for (std::size_t i = 0; i < rules.driven.size() && i < drop_marks.size(); ++i)
    if (rules.driven[i]) drop_marks[i] = 0;
  for (int iy = 0; iy < area.height; ++iy)
    for (int ix = 0; ix < area.width; ++ix)
      if (drop_marks[area.linear_index(ix, iy)] && off_goal(ix, iy))
        imp[area.linear_index(ix, iy)] = 1.f;
  if (rules.seen_no_ground_points <= 0) return out;
  // Seen well, its whole 3 x 3 window seen, and no ground plane (a cell left unknown by the map's
  // full-window rule has one: its elevation): impassable.
  std::vector<std::size_t> no_ground;
  for (int iy = 1; iy + 1 < area.height; ++iy)
    for (int ix = 1; ix + 1 < area.width; ++ix) {
      const std::size_t i = area.linear_index(ix, iy);
      if (std::isfinite(tau[i]) || std::isfinite(elevation[i]) ||
          pts[i] < float(rules.seen_no_ground_points))
        continue;
      bool window_seen = true;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          window_seen = window_seen && pts[area.linear_index(ix + dx, iy + dy)] > 0.f;
      if (window_seen) no_ground.push_back(i);
    }
  for (std::size_t i : no_ground) imp[i] = 1.f;
  return out;
}

void cost_shadows(Grid2D& grid, const Eigen::Vector2d& sensor_xy_m, double inner_m, double outer_m,
                  float shadow_tau) {
  const GridGeometry& g = grid.geometry();
  auto tau = grid.layer(L::kTraversability);
  auto pts = grid.layer(L::kPoints);
  for (int iy = 0; iy < g.height; ++iy)
    for (int ix = 0; ix < g.width; ++ix) {
      const std::size_t i = g.linear_index(ix, iy);
      const double d = (g.cell_center(ix, iy) - sensor_xy_m).norm();
      if (d <= inner_m || d >= outer_m || pts[i] > 0.f) continue;
      tau[i] = shadow_tau;
      pts[i] = 1.f;
    }
}

std::vector<std::uint8_t> known_blocked(const Grid2D& grid) {
  const auto tau = grid.layer(L::kTraversability);
  const bool has_imp = grid.has_layer(L::kImpassable);
  std::vector<std::uint8_t> out(tau.size(), 0);
  for (std::size_t i = 0; i < tau.size(); ++i)
    out[i] = (has_imp && grid.layer(L::kImpassable)[i] > 0.5f) ||
             (std::isfinite(tau[i]) && tau[i] <= 0.0f);
  return out;
}

std::vector<long> footprint_cells(const GridGeometry& geometry, const planning::Pose2& pose,
                                  const terrain::RobotConfig& robot) {
  return planning::rectangle_cells(geometry, pose, 0.5 * robot.length_m, 0.5 * robot.width_m);
}

void mark_driven(const GridGeometry& geometry, const planning::Pose2& pose,
                 const terrain::RobotConfig& robot, std::vector<std::uint8_t>& driven) {
  driven.resize(geometry.cell_count(), 0);
  const double c = std::cos(pose.yaw_rad), s = std::sin(pose.yaw_rad);
  for (long i : footprint_cells(geometry, pose, robot)) {
    if (i < 0) continue;
    const Eigen::Vector2d d =
        geometry.cell_center(int(i % geometry.width), int(i / geometry.width)) -
        Eigen::Vector2d(pose.x_m, pose.y_m);
    if (std::abs(c * d.x() + s * d.y()) <= 0.5 * robot.length_m &&
        std::abs(-s * d.x() + c * d.y()) <= 0.5 * robot.width_m)
      driven[std::size_t(i)] = 1;
  }
}

std::optional<planning::Pose2> nearest_free_pose(const planning::PlanningMap& map,
                                                 const planning::Pose2& goal, double tolerance_m) {
  if (map.pose_free(goal)) return goal;
  constexpr int kDirections = 16;
  for (double r = 0.05; r <= tolerance_m + 1e-9; r += 0.05)
    for (int k = 0; k < kDirections; ++k) {
      const double a = 2.0 * M_PI * k / kDirections;
      const planning::Pose2 p{goal.x_m + r * std::cos(a), goal.y_m + r * std::sin(a), goal.yaw_rad};
      if (map.pose_free(p)) return p;
    }
  return std::nullopt;
}

planning::Path straight_path(const planning::Pose2& start, double length_m, bool reverse,
                             double step_m) {
  planning::Path path;
  const int n = std::max(1, int(std::ceil(length_m / step_m)));
  const double sign = reverse ? -1.0 : 1.0;
  for (int k = 0; k <= n; ++k) {
    const double s = sign * length_m * k / n;
    path.push_back({{start.x_m + s * std::cos(start.yaw_rad),
                     start.y_m + s * std::sin(start.yaw_rad), start.yaw_rad},
                    reverse && k > 0});
  }
  return path;
}

void clear_under_robot(Grid2D& grid, const planning::Pose2& pose, const terrain::RobotConfig& robot,
                       double grow_m) {
  auto tau = grid.layer(L::kTraversability);
  const bool has_imp = grid.has_layer(L::kImpassable), has_pts = grid.has_layer(L::kPoints);
  for (long c : planning::rectangle_cells(grid.geometry(), pose, 0.5 * robot.length_m + grow_m,
                                          0.5 * robot.width_m + grow_m)) {
    if (c < 0) continue;
    const std::size_t i = std::size_t(c);
    tau[i] = std::isfinite(tau[i]) ? std::max(tau[i], 0.5f) : 0.5f;
    if (has_imp) grid.layer(L::kImpassable)[i] = 0.f;
    if (has_pts) grid.layer(L::kPoints)[i] = std::max(grid.layer(L::kPoints)[i], 1.f);
  }
}

}  // namespace fieldlidar::loops
