// Pure pursuit along a Hybrid A* path, one forward or reverse run at a time (the robot stops at
// each cusp), within the robot's speed, acceleration, yaw-rate and curvature limits.

#include "fieldlidar/planning/path_follower.hpp"

#include <algorithm>
#include <cmath>

namespace fieldlidar::planning {

PathFollower::PathFollower(FollowerConfig config) : config_(config) {}

void PathFollower::set_path(Path path) {
  path_ = std::move(path);
  s_m_.assign(path_.size(), 0.0);
  runs_.clear();
  run_ = index_ = 0;
  for (std::size_t i = 1; i < path_.size(); ++i)
    s_m_[i] = s_m_[i - 1] + std::hypot(path_[i].pose.x_m - path_[i - 1].pose.x_m,
                                       path_[i].pose.y_m - path_[i - 1].pose.y_m);
  // Sample i's flag tells how the robot drives into it: a run ends where the next flag differs.
  for (std::size_t i = 1; i < path_.size(); ++i) {
    if (runs_.empty() || runs_.back().reverse != path_[i].reverse)
      runs_.push_back({i - 1, i, path_[i].reverse});
    runs_.back().end = i;
  }
}

Pose2 PathFollower::lookahead_point(const Run& run, double s_m) const {
  if (s_m >= s_m_[run.end]) {
    // Beyond the run's end: on the straight line through the end along the driving direction,
    // so the robot closes in on the end pose rather than circling it.
    const Pose2& e = path_[run.end].pose;
    const double d = (s_m - s_m_[run.end]) * (run.reverse ? -1.0 : 1.0);
    return {e.x_m + d * std::cos(e.yaw_rad), e.y_m + d * std::sin(e.yaw_rad), e.yaw_rad};
  }
  const auto it =
      std::lower_bound(s_m_.begin() + long(run.begin), s_m_.begin() + long(run.end) + 1, s_m);
  const std::size_t i = std::max<std::size_t>(std::size_t(it - s_m_.begin()), run.begin + 1);
  const double seg = s_m_[i] - s_m_[i - 1];
  const double u = seg > 1e-9 ? std::clamp((s_m - s_m_[i - 1]) / seg, 0.0, 1.0) : 1.0;
  const Pose2& a = path_[i - 1].pose;
  const Pose2& b = path_[i].pose;
  return {a.x_m + u * (b.x_m - a.x_m), a.y_m + u * (b.y_m - a.y_m), b.yaw_rad};
}

DriveCommand PathFollower::command(const Pose2& pose, double v_now_m_s, double dt_s) {
  DriveCommand cmd;
  const auto brake = [&](DriveCommand c) {
    const double dv = config_.max_accel_m_s2 * dt_s;
    c.v_m_s = std::clamp(0.0, v_now_m_s - dv, v_now_m_s + dv);
    c.yaw_rate_rad_s = 0.0;
    return c;
  };
  if (runs_.empty()) {
    cmd.done = true;
    return brake(cmd);
  }
  const double kappa_max = 1.0 / config_.min_turn_radius_m;
  while (true) {
    const Run& run = runs_[run_];
    index_ = std::clamp(index_, run.begin, run.end);
    // Progress: the nearest sample within the next 2 m of the run (never backwards).
    double best = 1e18;
    for (std::size_t i = index_; i <= run.end && s_m_[i] <= s_m_[index_] + 2.0; ++i) {
      const double d = std::hypot(path_[i].pose.x_m - pose.x_m, path_[i].pose.y_m - pose.y_m);
      if (d < best) best = d, index_ = i;
    }
    const Pose2& e = path_[run.end].pose;
    const double dir = run.reverse ? -1.0 : 1.0;
    // Distance still to drive to the run's end, along the end heading once close.
    const double along =
        dir * ((e.x_m - pose.x_m) * std::cos(e.yaw_rad) + (e.y_m - pose.y_m) * std::sin(e.yaw_rad));
    double remaining = s_m_[run.end] - s_m_[index_];
    if (remaining < config_.lookahead_m) remaining = along;
    cmd.index = index_;
    cmd.cross_track_m = best;
    if (remaining > config_.end_tolerance_m) {
      cmd.remaining_m = remaining + (s_m_.back() - s_m_[run.end]);
      // Pure pursuit: the arc through the look-ahead point tangent to the robot's heading.
      const Pose2 target = lookahead_point(run, s_m_[index_] + config_.lookahead_m);
      const double dx = target.x_m - pose.x_m, dy = target.y_m - pose.y_m;
      const double c = std::cos(pose.yaw_rad), s = std::sin(pose.yaw_rad);
      const double lx = c * dx + s * dy, ly = -s * dx + c * dy;
      const double d2 = lx * lx + ly * ly;
      const double kappa = d2 > 1e-9 ? std::clamp(2.0 * ly / d2, -kappa_max, kappa_max) : 0.0;
      double speed = run.reverse ? config_.max_reverse_speed_m_s : config_.max_speed_m_s;
      speed = std::min(speed, std::max(config_.min_speed_m_s,
                                       std::sqrt(2.0 * config_.max_accel_m_s2 * remaining)));
      if (std::abs(kappa) > 1e-9)
        speed = std::min(speed, config_.max_yaw_rate_rad_s / std::abs(kappa));
      const double dv = config_.max_accel_m_s2 * dt_s;
      cmd.v_m_s = std::clamp(dir * speed, v_now_m_s - dv, v_now_m_s + dv);
      cmd.yaw_rate_rad_s = cmd.v_m_s * kappa;
      return cmd;
    }
    // This run is done: stop before the next (a cusp) or at the end.
    if (run_ + 1 >= runs_.size()) {
      cmd.done = true;
      return brake(cmd);
    }
    if (std::abs(v_now_m_s) > config_.min_speed_m_s + 1e-9 &&
        (v_now_m_s > 0) != !runs_[run_ + 1].reverse)
      return brake(cmd);  // still rolling the old way: brake first
    ++run_;
    index_ = runs_[run_].begin;
  }
}

Pose2 integrate_unicycle(const Pose2& pose, double v, double w, double dt) {
  Pose2 out = pose;
  if (std::abs(w) < 1e-9) {
    out.x_m += v * dt * std::cos(pose.yaw_rad);
    out.y_m += v * dt * std::sin(pose.yaw_rad);
  } else {
    const double r = v / w, yaw1 = pose.yaw_rad + w * dt;
    out.x_m += r * (std::sin(yaw1) - std::sin(pose.yaw_rad));
    out.y_m -= r * (std::cos(yaw1) - std::cos(pose.yaw_rad));
    out.yaw_rad = wrap_angle(yaw1);
  }
  return out;
}

}  // namespace fieldlidar::planning
