// The navigate loop (seed 004 in closed loop): scan -> fused traversability map -> Hybrid A* ->
// pure pursuit -> motion, re-planning when the map blocks the path, makes it costlier, or a period
// has passed; the truth is only read to score the run (and to plan the reference path).

#include "fieldlidar/loops/navigate.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <numeric>
#include <optional>
#include <utility>

#include <fmt/core.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/loops/navigate_maps.hpp"
#include "fieldlidar/loops/navigate_poses.hpp"
#include "fieldlidar/planning/path_check.hpp"
#include "fieldlidar/planning/planner_for_robot.hpp"
#include "fieldlidar/sim/lidar_simulator.hpp"
#include "fieldlidar/sim/motion.hpp"
#include "fieldlidar/terrain/robot_config.hpp"

namespace fieldlidar::loops {
namespace {

using planning::PlanStatus;
using planning::Pose2;
using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

bool finite(const Pose2& p) {
  return std::isfinite(p.x_m) && std::isfinite(p.y_m) && std::isfinite(p.yaw_rad);
}

/// The loop's state in one object; each step is a member so that run() reads like the loop.
class Loop {
 public:
  Loop(const sim::Scene& scene, const SensorModel& sensor, const NavigateConfig& config)
      : scene_(scene),
        sensor_(sensor),
        cfg_(config),
        robot_(config.fusion.layers.robot),
        planner_cfg_(planning::planner_config_for(robot_, config.planner)),
        lidar_(scene, sensor, sim::SimConfig{.seed = config.sim_seed}),
        map_(config.fusion) {
    planning::FollowerConfig f = config.follower;
    f.min_turn_radius_m = robot_.min_turn_radius_m;
    follower_ = planning::PathFollower(f);
    area_ = GridGeometry::covering(scene.min_m(), scene.max_m(), config.fusion.layers.cell_m);
    const double lowest = sensor.beam_altitudes_rad.empty() ? 0.0 : sensor.beam_altitudes_rad[0];
    if (lowest < -0.01) blind_radius_m_ = scene.sensor_height_m() / std::tan(-lowest);
  }

  NavigateResult run(const Pose2& start, const Pose2& goal);

 private:
  void score_truth_plan();
  void scan();
  std::string replan_trigger();
  void plan(const std::string& trigger);
  /// The cold start's straight creep (NavigateConfig::start_creep_m) as the first plan; false
  /// when it is off or both lanes are blocked.
  bool start_creep();
  /// True when the next pose's footprint would enter a cell the map knows to be impassable that
  /// the robot does not already stand on.
  bool enters_known_blocked(const Pose2& next) const;
  bool on_truth_impassable(const Pose2& pose) const;
  void finish(NavigateOutcome outcome, std::string reason, NavigateState state) {
    r_.outcome = outcome;
    r_.reason = std::move(reason);
    state_ = state;
    done_ = true;
  }

  const sim::Scene& scene_;
  const SensorModel& sensor_;
  NavigateConfig cfg_;
  terrain::RobotConfig robot_;
  planning::PlannerConfig planner_cfg_;
  sim::LidarSimulator lidar_;
  terrain::TerrainMap map_;
  planning::PathFollower follower_;
  GridGeometry area_;
  Grid2D truth_;
  std::vector<std::uint8_t> truth_blocked_, blocked_;
  Grid2D grid_;                                       ///< the fused map on the area (planner input)
  std::unique_ptr<planning::PlanningMap> check_map_;  ///< the planner's view of grid_
  std::vector<double> step_costs_;  ///< the current plan's step costs when it was made
  NavigateResult r_;
  Pose2 pose_, goal_;                   ///< pose_: the truth (motion, scoring)
  std::optional<NavigatePoses> poses_;  ///< the pose the robot works with (me())
  const Pose2& me() const { return poses_->estimate(); }
  double t_ = 0, v_ = 0, last_plan_t_ = -1e9, scan_ms_ = 0, plan_ms_ = 0;
  double blind_radius_m_ = 0;  ///< no ground return nearer the sensor than this (m)
  bool map_updated_ = false, done_ = false;
  bool creeping_ = false;  ///< following the cold start's creep
  std::string pending_;    ///< a re-plan asked for by the last control step
  int unreachable_votes_ = 0, planner_failures_ = 0, off_goal_plans_ = 0;
  NavigateState state_ = NavigateState::kPlanning;
};

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

void Loop::scan() {
  const auto t0 = Clock::now();
  const sim::SimFrame frame = lidar_.scan(t_, poses_->lidar_pose(pose_));
  map_.add_scan(frame.cloud, sensor_, poses_->place_sweep(frame.cloud, t_, pose_));
  grid_ = area_grid(map_, area_, cfg_.seen_no_ground_points, {me().x_m, me().y_m}, blind_radius_m_);
  blocked_ = known_blocked(grid_);
  check_map_ = std::make_unique<planning::PlanningMap>(grid_, robot_, planner_cfg_.map);
  map_updated_ = true;
  ++r_.scans;
  scan_ms_ += ms_since(t0);
}

std::string Loop::replan_trigger() {
  if (!pending_.empty()) return std::exchange(pending_, "");
  if (!follower_.has_path()) return map_updated_ ? (r_.plans.empty() ? "start" : "retry") : "";
  if (map_updated_) {
    const std::size_t k = follower_.index();
    if (planning::first_blocked_sample(*check_map_, follower_.path(), k)) return "blocked";
    const auto now = planning::path_step_costs(
        *check_map_, follower_.path(), planner_cfg_.tau_weight, planner_cfg_.reverse_factor);
    const double before =
        std::accumulate(step_costs_.begin() + long(k) + 1, step_costs_.end(), 0.0);
    const double after = std::accumulate(now.begin() + long(k) + 1, now.end(), 0.0);
    if (after > (1.0 + cfg_.replan_cost_rise) * before + 1e-6 && !creeping_) return "cost";
  }
  if (creeping_) return "";  // the creep runs its course unless blocked
  if (t_ - last_plan_t_ >= cfg_.replan_period_s && map_updated_) return "period";
  return "";
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
    step_costs_ = planning::path_step_costs(*check_map_, path, planner_cfg_.tau_weight,
                                            planner_cfg_.reverse_factor);
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
  const auto t0 = Clock::now();
  Grid2D grid = grid_;
  if (cfg_.shadow_radius_m > blind_radius_m_)
    cost_shadows(grid, {me().x_m, me().y_m}, blind_radius_m_ + grid.geometry().resolution_m,
                 cfg_.shadow_radius_m, float(cfg_.shadow_tau));
  // A goal whose footprint the map blocks (an obstacle's halo) is moved to the nearest free pose
  // within the goal tolerance less 0.1 m for the follower's error, where arriving still counts.
  Pose2 target = goal_;
  if (!check_map_->pose_free(goal_))
    if (const auto free = nearest_free_pose(*check_map_, goal_, cfg_.goal_tolerance_m - 0.1))
      target = *free;
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
    planning::HybridAStar planner(grid, robot_, big);
    p = planner.plan(me(), target);
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
  if (p.ok()) {
    step_costs_ = planning::path_step_costs(*check_map_, p.path, planner_cfg_.tau_weight,
                                            planner_cfg_.reverse_factor);
    follower_.set_path(std::move(p.path));
    unreachable_votes_ = planner_failures_ = 0;
    state_ = NavigateState::kDriving;
    return;
  }
  follower_.clear();
  state_ = NavigateState::kPlanning;
  const bool no_way = p.status == PlanStatus::kNoPath || p.status == PlanStatus::kGoalInCollision ||
                      p.status == PlanStatus::kGoalOffMap;
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

bool Loop::enters_known_blocked(const Pose2& next) const {
  const auto now = footprint_cells(area_, me(), robot_);
  for (long c : footprint_cells(area_, next, robot_)) {
    if (c < 0) return std::find(now.begin(), now.end(), c) == now.end();
    if (blocked_[std::size_t(c)] && std::find(now.begin(), now.end(), c) == now.end()) return true;
  }
  return false;
}

bool Loop::on_truth_impassable(const Pose2& pose) const {
  for (long c : footprint_cells(area_, pose, robot_))
    if (c < 0 || truth_blocked_[std::size_t(c)]) return true;
  return false;
}

NavigateResult Loop::run(const Pose2& start, const Pose2& goal) {
  const auto wall0 = Clock::now();
  r_.start = pose_ = start;
  poses_.emplace(scene_, sensor_, start,
                 cfg_.pose_source == PoseSource::kOdometry
                     ? std::optional<odometry::OdometryConfig>(cfg_.odometry)
                     : std::nullopt,
                 cfg_.streams);
  r_.goal = goal_ = goal;
  const auto& L = cfg_.fusion.layers;
  truth_ = scene_.terrain_truth({.resolution_m = L.cell_m,
                                 .max_slope_deg = robot_.max_slope_deg,
                                 .max_step_m = robot_.max_step_m,
                                 .robot_clearance_m = robot_.clearance_m,
                                 .min_obstacle_height_m = robot_.min_obstacle_height_m});
  area_ = truth_.geometry();
  const auto passable = truth_.layer("passable");
  truth_blocked_.resize(passable.size());
  for (std::size_t i = 0; i < passable.size(); ++i) truth_blocked_[i] = passable[i] < 0.5f;
  score_truth_plan();

  const double straight = std::hypot(goal.x_m - start.x_m, goal.y_m - start.y_m);
  const double max_time =
      cfg_.max_time_s > 0 ? cfg_.max_time_s : 40.0 + 4.0 * straight / cfg_.follower.max_speed_m_s;
  const double dt = cfg_.control_period_s;
  double next_scan = 0.0;
  while (!done_) {
    if (t_ + 1e-9 >= next_scan) {
      scan();
      next_scan += cfg_.scan_period_s;
    }
    if (const std::string trigger = replan_trigger(); !trigger.empty()) plan(trigger);
    map_updated_ = false;
    if (done_) break;
    planning::DriveCommand cmd;
    if (follower_.has_path()) {
      cmd = follower_.command(me(), v_, dt);
      if (creeping_) {
        cmd.v_m_s = std::clamp(cmd.v_m_s, -cfg_.creep_speed_m_s, cfg_.creep_speed_m_s);
        if (cmd.done) {  // the creep is over: plan to the goal
          creeping_ = false;
          follower_.clear();
          pending_ = "creep_done";
          cmd.done = false;
        }
      }
    } else {
      const double dv = cfg_.follower.max_accel_m_s2 * dt;
      cmd.v_m_s = std::clamp(0.0, v_ - dv, v_ + dv);
    }
    if (cmd.done && std::abs(cmd.v_m_s) < 1e-9) {
      const double d = std::hypot(goal.x_m - me().x_m, goal.y_m - me().y_m);
      const double dyaw = std::abs(planning::wrap_angle(goal.yaw_rad - me().yaw_rad));
      if (d <= cfg_.goal_tolerance_m && dyaw <= cfg_.goal_yaw_tolerance_rad) {
        finish(NavigateOutcome::kArrived,
               fmt::format("at the goal: {:.2f} m, {:.2f} rad off", d, dyaw),
               NavigateState::kArrived);
      } else if (++off_goal_plans_ > 5) {
        finish(NavigateOutcome::kFailed,
               fmt::format("the plans end {:.2f} m, {:.2f} rad off the goal", d, dyaw),
               NavigateState::kFailed);
      } else {
        pending_ = "off_goal";
        follower_.clear();
      }
    }
    Pose2 next = planning::integrate_unicycle(pose_, cmd.v_m_s, cmd.yaw_rate_rad_s, dt);
    if (!done_ && enters_known_blocked(
                      planning::integrate_unicycle(me(), cmd.v_m_s, cmd.yaw_rate_rad_s, dt))) {
      cmd.v_m_s = cmd.yaw_rate_rad_s = 0.0;  // emergency stop, then re-plan
      next = pose_;
      pending_ = "safety_stop";
      state_ = NavigateState::kSafetyStop;
      if (++r_.safety_stops > cfg_.max_safety_stops)
        finish(NavigateOutcome::kFailed,
               fmt::format("{} emergency stops before known-impassable cells", r_.safety_stops),
               NavigateState::kFailed);
    } else if (!done_ && follower_.has_path()) {
      state_ = NavigateState::kDriving;
    }
    NavigateLogRow row;
    row.t_s = t_;
    row.x_m = pose_.x_m;
    row.y_m = pose_.y_m;
    row.yaw_rad = pose_.yaw_rad;
    row.v_m_s = cmd.v_m_s;
    row.yaw_rate_rad_s = cmd.yaw_rate_rad_s;
    row.planned_length_m = follower_.has_path() ? cmd.remaining_m : NAN;
    if (const auto c = area_.cell_of({pose_.x_m, pose_.y_m})) {
      row.cell_ix = c->x();
      row.cell_iy = c->y();
      row.cell_passable = truth_blocked_[area_.linear_index(c->x(), c->y())] ? 0 : 1;
    }
    row.footprint_on_impassable = on_truth_impassable(pose_);
    r_.frames_on_impassable += row.footprint_on_impassable;
    row.state = state_;
    row.replans = r_.replans;
    r_.rows.push_back(row);
    r_.driven.push_back(pose_);
    if (done_) break;
    r_.driven_length_m += std::hypot(next.x_m - pose_.x_m, next.y_m - pose_.y_m);
    r_.max_pose_error_m =
        std::max(r_.max_pose_error_m, std::hypot(me().x_m - pose_.x_m, me().y_m - pose_.y_m));
    poses_->advance(pose_, cmd.v_m_s, cmd.yaw_rate_rad_s, dt);
    pose_ = next;
    v_ = cmd.v_m_s;
    t_ += dt;
    if (t_ > max_time)
      finish(NavigateOutcome::kFailed, fmt::format("time limit {:.0f} s reached", max_time),
             NavigateState::kFailed);
  }
  r_.duration_s = t_;
  r_.odometry_unregistered = poses_->unregistered();
  r_.pose_source = cfg_.pose_source;
  if (std::isfinite(r_.truth_length_m) && r_.truth_length_m > 0)
    r_.length_ratio = r_.driven_length_m / r_.truth_length_m;
  r_.scan_ms = r_.scans ? scan_ms_ / double(r_.scans) : 0.0;
  r_.plan_ms = r_.plans.empty() ? 0.0 : plan_ms_ / double(r_.plans.size());
  r_.built_map = std::move(grid_);
  r_.truth = std::move(truth_);
  r_.wall_s = ms_since(wall0) / 1000.0;
  return std::move(r_);
}

}  // namespace

NavigateResult run_navigate(const sim::Scene& scene, const SensorModel& sensor,
                            const planning::Pose2& start, const planning::Pose2& goal,
                            const NavigateConfig& config) {
  terrain::check_robot_config(config.fusion.layers.robot, "navigate: robot");
  if (!finite(start) || !finite(goal)) throw Error("navigate: start and goal must be finite");
  for (const auto& [name, p] : {std::pair{"start", start}, std::pair{"goal", goal}})
    if (p.x_m < scene.min_m().x() || p.y_m < scene.min_m().y() || p.x_m > scene.max_m().x() ||
        p.y_m > scene.max_m().y())
      throw Error(
          fmt::format("navigate: {} ({:.2f}, {:.2f}) m is off the scene", name, p.x_m, p.y_m));
  if (!(config.control_period_s > 0 && config.control_period_s <= 1.0) ||
      !(config.scan_period_s >= config.control_period_s && config.scan_period_s <= 10.0) ||
      !(config.replan_period_s > 0))
    throw Error(
        "navigate: control_period_s must be in (0, 1], scan_period_s in "
        "[control_period_s, 10] and replan_period_s > 0");
  Loop loop(scene, sensor, config);
  return loop.run(start, goal);
}

}  // namespace fieldlidar::loops
