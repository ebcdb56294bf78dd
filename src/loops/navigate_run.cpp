// The navigate loop's control loop: every control period scan when a sweep is due, re-plan when
// asked, follow the plan (or stop), stop before a known-impassable cell, log, score, move.

#include <algorithm>
#include <cmath>
#include <utility>

#include <fmt/core.h>

#include "fieldlidar/planning/path_follower.hpp"
#include "navigate_loop.hpp"

namespace fieldlidar::loops::detail {

NavigateResult Loop::run(const Pose2& start, const Pose2& goal) {
  const auto wall0 = Clock::now();
  r_.start = pose_ = start;
  poses_.emplace(scene_, sensor_, start,
                 cfg_.pose_source == PoseSource::kOdometry
                     ? std::optional<odometry::OdometryConfig>(cfg_.odometry)
                     : std::nullopt,
                 cfg_.streams, cfg_.lidar_pitch_deg * M_PI / 180.0);
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
  approach();

  const double straight = std::hypot(goal.x_m - start.x_m, goal.y_m - start.y_m);
  const double max_time =
      cfg_.max_time_s > 0 ? cfg_.max_time_s : 40.0 + 4.0 * straight / cfg_.follower.max_speed_m_s;
  const double dt = cfg_.control_period_s;
  double next_scan = 0.0;
  while (!done_) {
    if (cfg_.driven_clears_guesses) mark_driven(area_, me(), robot_, driven_);
    if (t_ + 1e-9 >= next_scan) {
      scan();
      next_scan += cfg_.scan_period_s;
    }
    if (const std::string trigger = replan_trigger(); !trigger.empty()) plan(trigger);
    map_updated_ = false;
    if (done_) break;
    planning::DriveCommand cmd;
    if (looking()) {  // turn in place; the first plan follows
      cmd.yaw_rate_rad_s = cfg_.look_yaw_rate_rad_s;
      looked_rad_ += cfg_.look_yaw_rate_rad_s * dt;
      if (!looking()) pending_ = "start";
    } else if (follower_.has_path()) {
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
      } else if (look_trip_) {  // at the viewpoint: plan again with what it saw
        look_trip_ = false;
        follower_.clear();
        pending_ = "looked";
      } else if (held_.size() > 0) {  // at the hold point: look again (the detour, mostly)
        pending_ = "hold";
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
    const double tilt_rad = chassis_tilt_rad(pose_);  // the IMU's reading, stop and log alike
    const bool tilted = !done_ && tilt_stop(v_, tilt_rad);
    if (tilted || (!done_ && enters_known_blocked(planning::integrate_unicycle(
                                 me(), cmd.v_m_s, cmd.yaw_rate_rad_s, dt)))) {
      cmd.v_m_s = cmd.yaw_rate_rad_s = 0.0;  // emergency stop, then re-plan
      next = pose_;
      if (tilted) {  // the leading cells are felt; the plan that led there is dropped
        pending_ = "tilt";
        follower_.clear();
        ++r_.tilt_stops;
      } else {
        pending_ = looking() ? "start" : "safety_stop";
        looked_rad_ = std::max(looked_rad_, cfg_.start_look_rad);  // a blocked look ends there
      }
      state_ = NavigateState::kSafetyStop;
      if (++r_.safety_stops > cfg_.max_safety_stops)
        finish(NavigateOutcome::kFailed,
               fmt::format("{} emergency stops before known-impassable cells{}", r_.safety_stops,
                           tilted ? " or tilted over" : ""),
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
    if (row.footprint_on_impassable) row.impassable_depth_m = truth_impassable_depth_m(pose_);
    r_.max_impassable_depth_m = std::max(r_.max_impassable_depth_m, row.impassable_depth_m);
    row.obstacle_gap_m = obstacle_gap_m(pose_);
    r_.frames_on_obstacles += row.obstacle_gap_m < 0.0;
    r_.min_obstacle_gap_m = std::min(r_.min_obstacle_gap_m, row.obstacle_gap_m);
    row.tilt_deg = tilt_rad * 180.0 / M_PI;
    row.tilted_over = row.tilt_deg > robot_.max_slope_deg;
    r_.max_tilt_deg = std::max(r_.max_tilt_deg, row.tilt_deg);
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
  r_.blind_radius_m = blind_radius_m_;
  if (std::isfinite(r_.truth_length_m) && r_.truth_length_m > 0)
    r_.length_ratio = r_.driven_length_m / r_.truth_length_m;
  r_.scan_ms = r_.scans ? scan_ms_ / double(r_.scans) : 0.0;
  r_.plan_ms = r_.plans.empty() ? 0.0 : plan_ms_ / double(r_.plans.size());
  r_.built_map = std::move(grid_);
  r_.truth = std::move(truth_);
  r_.map_agreement = map_agreement(r_.built_map, r_.truth, r_.driven, kMapAgreementRadiusM);
  r_.wall_s = ms_since(wall0) / 1000.0;
  return std::move(r_);
}

}  // namespace fieldlidar::loops::detail
