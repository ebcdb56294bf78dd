// The navigate loop's planning: the reference plan on the truth, when to re-plan (blocked,
// costlier, a period), the cold start's creep, and a plan on the built map with its retries.

#include <algorithm>
#include <cmath>
#include <numeric>
#include <utility>

#include <fmt/core.h>

#include "fieldlidar/loops/navigate_maps.hpp"
#include "fieldlidar/planning/path_check.hpp"
#include "navigate_loop.hpp"

namespace fieldlidar::loops::detail {

void Loop::score_truth_plan() {
  if (!cfg_.plan_on_truth) return;
  planning::HybridAStar planner(truth_planning_grid(truth_, cfg_.fusion.layers), robot_,
                                planner_cfg_);
  const planning::PlanResult p = planner.plan(r_.start, goal_);
  r_.truth_status = p.status;
  if (p.ok()) {
    r_.truth_path = p.path;
    r_.truth_length_m = planning::path_length_m(p.path);
  }
}

std::vector<double> Loop::step_costs(const planning::Path& path) const {
  return planning::path_step_costs(*check_map_, path, planner_cfg_.tau_weight,
                                   planner_cfg_.reverse_factor);
}

double Loop::rest_cost() const {
  const auto now = step_costs(follower_.path());
  return std::accumulate(now.begin() + long(follower_.index()) + 1, now.end(), 0.0);
}

std::string Loop::replan_trigger() {
  if (looking()) return "";  // the first plan waits for the start look
  if (!pending_.empty()) return std::exchange(pending_, "");
  if (!follower_.has_path()) return map_updated_ ? (r_.plans.empty() ? "start" : "retry") : "";
  if (!held_.empty() && map_updated_) return "hold";  // the hold looks again at every update
  if (map_updated_) {
    const std::size_t k = follower_.index();
    if (planning::first_blocked_sample(*check_map_, follower_.path(), k)) return "blocked";
    const double before =
        std::accumulate(step_costs_.begin() + long(k) + 1, step_costs_.end(), 0.0);
    if (rest_cost() > (1.0 + cfg_.replan_cost_rise) * before + 1e-6 && !creeping_) return "cost";
  }
  if (creeping_) return "";  // the creep runs its course unless blocked
  if (t_ - last_plan_t_ >= cfg_.replan_period_s && map_updated_) return "period";
  return "";
}

bool Loop::keeps_its_plan(const planning::Path& candidate) const {
  if (!(cfg_.replan_switch_gain > 0) || !follower_.has_path()) return false;
  const double now = rest_cost();
  const auto next = step_costs(candidate);
  const double then = std::accumulate(next.begin(), next.end(), 0.0);
  return std::isfinite(now) && then > (1.0 - cfg_.replan_switch_gain) * now;
}

bool Loop::start_creep() {
  const double length = cfg_.start_creep_m < 0 ? blind_radius_m_ : cfg_.start_creep_m;
  if (!(length > 0)) return false;
  // Forward, or backwards when the goal lies behind; the other way when that lane is blocked.
  const double bearing = std::atan2(goal_.y_m - me().y_m, goal_.x_m - me().x_m);
  const bool behind = std::cos(planning::wrap_angle(bearing - me().yaw_rad)) < 0;
  for (bool reverse : {behind, !behind}) {
    planning::Path path = straight_path(me(), length, reverse);
    if (const auto k = planning::first_blocked_sample(*check_map_, path)) {
      if (*k < 2) continue;
      path.resize(*k - 1);  // up to the last free sample
    }
    PlanRecord rec{
        t_, me(), PlanStatus::kSuccess, "start_creep", path, planning::path_length_m(path), 0.0, 0};
    r_.plans.push_back(std::move(rec));
    step_costs_ = step_costs(path);
    follower_.set_path(std::move(path));
    last_plan_t_ = t_;
    creeping_ = true;
    state_ = NavigateState::kDriving;
    return true;
  }
  return false;
}

void Loop::plan(const std::string& trigger) {
  if (trigger == "start" && r_.plans.empty() && start_creep()) return;
  creeping_ = false;
  if (hold_before_plan(trigger)) return;
  const auto t0 = Clock::now();
  Grid2D grid = grid_;
  if (cfg_.shadow_radius_m > blind_radius_m_)
    cost_shadows(grid, {me().x_m, me().y_m}, blind_radius_m_ + grid.geometry().resolution_m,
                 cfg_.shadow_radius_m, float(cfg_.shadow_tau));
  if (cfg_.start_disk_tau > 0)
    cost_shadows(grid, {r_.start.x_m, r_.start.y_m}, 0.0, blind_radius_m_,
                 float(cfg_.start_disk_tau));
  // A goal whose footprint the map blocks (an obstacle's halo) is moved to the nearest free pose
  // within the goal tolerance less 0.1 m for the follower's error, where arriving still counts;
  // seen blocked from farther than blocked_goal_look_m, to the nearest within
  // blocked_goal_approach_m, where the robot goes to look again.
  const double reach_m =
      cfg_.blocked_goal_look_m > 0 &&
              std::hypot(goal_.x_m - me().x_m, goal_.y_m - me().y_m) > cfg_.blocked_goal_look_m
          ? std::max(cfg_.blocked_goal_approach_m, cfg_.goal_tolerance_m - 0.1)
          : cfg_.goal_tolerance_m - 0.1;
  Pose2 target = goal_;
  if (!check_map_->pose_free(goal_))
    if (const auto free = nearest_free_pose(*check_map_, goal_, reach_m)) target = *free;
  planning::PlanResult p;
  {
    planning::HybridAStar planner(grid, robot_, planner_cfg_);
    p = planner.plan(me(), target);
  }
  if (p.status == PlanStatus::kTimedOut || p.status == PlanStatus::kExpansionLimit) {
    // An exhaustive search (a goal walled in) outgrows the budget of one control period: once
    // more with cfg_.retry_budget_factor times the time and expansions.
    planning::PlannerConfig big = planner_cfg_;
    big.time_budget_ms *= cfg_.retry_budget_factor;
    big.max_expansions = int(big.max_expansions * cfg_.retry_budget_factor);
    if (cfg_.retry_lattice_cell_m > grid.geometry().resolution_m)
      big.lattice_cell_m = std::max(big.lattice_cell_m, cfg_.retry_lattice_cell_m);
    planning::HybridAStar planner(grid, robot_, big);
    p = planner.plan(me(), target);
  }
  if (p.status == PlanStatus::kStartInCollision && cfg_.escape_max_m > 0) {
    // Beside an obstacle: out by the shortest move the step check allows, then on by a plan.
    const double bearing = std::atan2(target.y_m - me().y_m, target.x_m - me().x_m);
    const bool behind = std::cos(planning::wrap_angle(bearing - me().yaw_rad)) < 0;
    if (auto out = escape_path(*check_map_, blocked_, me(), behind, cfg_.escape_max_m)) {
      planning::HybridAStar planner(grid, robot_, planner_cfg_);
      planning::PlanResult q = planner.plan(out->back().pose, target);
      if (q.ok()) {
        out->insert(out->end(), q.path.begin() + 1, q.path.end());
        q.path = std::move(*out);
        p = std::move(q);
        ++r_.escapes;
      }
    }
  }
  if (p.status == PlanStatus::kStartInCollision) {
    // The robot stands there: the cells under it are passable whatever the map says (a halo,
    // a margin); clear them for the planner only (the step check still guards new cells).
    clear_under_robot(grid, me(), robot_, 0.3);
    planning::HybridAStar planner(grid, robot_, planner_cfg_);
    p = planner.plan(me(), target);
  }
  const double ms = ms_since(t0);
  plan_ms_ += ms;
  last_plan_t_ = t_;
  PlanRecord rec{t_,          me(),        p.status,
                 trigger,     p.path,      planning::path_length_m(p.path),
                 p.search_ms, p.expansions};
  r_.plans.push_back(std::move(rec));
  if (r_.plans.size() > 1) ++r_.replans;
  if (p.ok() && hold_instead_of(planning::path_length_m(r_.plans.back().path))) return;
  if (p.ok() && trigger == "period" && keeps_its_plan(p.path)) {
    ++r_.plans_put_off;
    return;
  }
  if (p.ok()) {
    look_trip_ = false;
    step_costs_ = step_costs(p.path);
    follower_.set_path(std::move(p.path));
    unreachable_votes_ = planner_failures_ = 0;
    state_ = NavigateState::kDriving;
    return;
  }
  const bool no_way = p.status == PlanStatus::kNoPath || p.status == PlanStatus::kGoalInCollision ||
                      p.status == PlanStatus::kGoalOffMap;
  if (look_trip_ && follower_.has_path()) return;  // on the way to look: the look goes on
  if (no_way && look_at_guesses(target)) return;
  look_trip_ = false;
  follower_.clear();
  state_ = NavigateState::kPlanning;
  if (no_way && ++unreachable_votes_ >= 2)
    finish(NavigateOutcome::kUnreachable,
           fmt::format("{} on two successive map updates", planning::to_string(p.status)),
           NavigateState::kUnreachable);
  else if (!no_way && ++planner_failures_ >= 3)
    finish(
        NavigateOutcome::kFailed,
        fmt::format("the planner failed three times in a row ({})", planning::to_string(p.status)),
        NavigateState::kFailed);
}

}  // namespace fieldlidar::loops::detail
