// The navigate loop's look before giving up: a goal the map cuts off only by guessed drops in the
// blind disk (cells no sweep has seen, marked impassable by mark_blind_drops) is not reported
// unreachable before those cells were looked at from beyond the blind disk.

#include <algorithm>
#include <cmath>
#include <utility>

#include "fieldlidar/loops/navigate_maps.hpp"
#include "fieldlidar/planning/path_check.hpp"
#include "fieldlidar/planning/planning_map.hpp"
#include "navigate_loop.hpp"

namespace fieldlidar::loops::detail {

namespace {

namespace L = terrain::layer;

/// How many viewpoints are planned to, nearest first, before the look is given up.
constexpr int kViewpointPlans = 6;

Eigen::Vector2d centre_of(const GridGeometry& g, std::size_t i) {
  return g.cell_center(int(i % std::size_t(g.width)), int(i / std::size_t(g.width)));
}

}  // namespace

std::vector<std::size_t> Loop::guesses_in_the_way(const Pose2& target) const {
  if (drop_marks_.empty()) return {};
  // The planner's map with the guesses not yet looked at taken as unknown.
  Grid2D relaxed = grid_;
  auto tau = relaxed.layer(L::kTraversability), imp = relaxed.layer(L::kImpassable);
  bool any = false;
  for (std::size_t i = 0; i < drop_marks_.size(); ++i)
    if (drop_marks_[i] == kBlindDropMark && !looked_[i] && !(i < felt_.size() && felt_[i])) {
      tau[i] = imp[i] = NAN;
      any = true;
    }
  if (!any) return {};
  const planning::PlanningMap map(relaxed, robot_, planner_cfg_.map);
  const auto free = nearest_free_pose(map, target, cfg_.goal_tolerance_m - 0.1);
  if (!free) return {};
  planning::HybridAStar planner(relaxed, robot_, planner_cfg_);
  const planning::PlanResult p = planner.plan(me(), *free);
  if (!p.ok()) return {};
  // The guesses under the footprint (with the planner's margin) along that plan.
  std::vector<std::uint8_t> on(drop_marks_.size(), 0);
  std::vector<std::size_t> cells;
  const double grow = planner_cfg_.map.footprint_margin_m;
  for (const auto& s : p.path)
    for (long c : planning::rectangle_cells(area_, s.pose, 0.5 * robot_.length_m + grow,
                                            0.5 * robot_.width_m + grow))
      if (c >= 0 && drop_marks_[std::size_t(c)] == kBlindDropMark && !looked_[std::size_t(c)] &&
          !on[std::size_t(c)]) {
        on[std::size_t(c)] = 1;
        cells.push_back(std::size_t(c));
      }
  return cells;
}

bool Loop::look_at_guesses(const Pose2& target) {
  if (r_.guess_looks >= cfg_.guess_looks) return false;
  looked_.resize(area_.cell_count(), 0);
  const std::vector<std::size_t> guesses = guesses_in_the_way(target);
  if (guesses.empty()) return false;
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  for (std::size_t i : guesses) centre += centre_of(area_, i);
  centre /= double(guesses.size());
  // Viewpoints on rings round the guesses' centre (near to near + depth), from which every guess
  // lies beyond the blind disk by the margin and within twice the depth more (where the map
  // still reads ground well), nearest the robot first.
  const double near = blind_radius_m_ + cfg_.guess_look_margin_m;
  const double far = near + 2.0 * cfg_.guess_look_depth_m;
  const auto sees_all_from = [&](const Eigen::Vector2d& xy) {
    for (std::size_t i : guesses) {
      const double d = (centre_of(area_, i) - xy).norm();
      if (d < near || d > far) return false;
    }
    return true;
  };
  if (sees_all_from({me().x_m, me().y_m})) {  // looked at from here already: they stand
    for (std::size_t i : guesses) looked_[i] = 1;
    return false;
  }
  std::vector<std::pair<double, Pose2>> views;
  for (double r = near; r <= near + cfg_.guess_look_depth_m + 1e-9; r += 1.0)
    for (int k = 0; k < 16; ++k) {
      const double a = 2.0 * M_PI * k / 16.0;
      const Eigen::Vector2d xy = centre + r * Eigen::Vector2d(std::cos(a), std::sin(a));
      const Pose2 view{xy.x(), xy.y(), std::atan2(centre.y() - xy.y(), centre.x() - xy.x())};
      if (check_map_->pose_free(view) && sees_all_from(xy))
        views.emplace_back(std::hypot(xy.x() - me().x_m, xy.y() - me().y_m), view);
    }
  std::sort(views.begin(), views.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  for (std::size_t v = 0; v < views.size() && int(v) < kViewpointPlans; ++v) {
    planning::HybridAStar planner(grid_, robot_, planner_cfg_);
    planning::PlanResult p = planner.plan(me(), views[v].second);
    if (!p.ok()) continue;
    for (std::size_t i : guesses) looked_[i] = 1;  // seen from there, or given up on
    r_.plans.push_back({t_, me(), p.status, "look", p.path, planning::path_length_m(p.path),
                        p.search_ms, p.expansions});
    step_costs_ = step_costs(p.path);
    follower_.set_path(std::move(p.path));
    look_trip_ = true;
    held_.clear();  // the look replaces a detour put off
    unreachable_votes_ = 0;
    ++r_.guess_looks;
    state_ = NavigateState::kDriving;
    return true;
  }
  return false;
}

}  // namespace fieldlidar::loops::detail
