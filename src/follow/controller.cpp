#include "fieldlidar/follow/controller.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fieldlidar::follow {

std::string to_string(FollowState s) {
  switch (s) {
    case FollowState::kIdle:
      return "idle";
    case FollowState::kFollowing:
      return "following";
    case FollowState::kTooClose:
      return "too_close";
    case FollowState::kTooFar:
      return "too_far";
    case FollowState::kLost:
      return "lost";
  }
  return "unknown";
}

FollowState check_safety(const std::optional<Eigen::Vector2d>& target, const SafetyConfig& c) {
  if (!target || !target->allFinite()) return FollowState::kLost;
  const double l = std::hypot(target->x(), target->y());  // seed 000: L = sqrt(xc^2 + yc^2)
  if (l < c.safe_distance_m) return FollowState::kTooClose;
  if (l > c.max_distance_m) return FollowState::kTooFar;
  return FollowState::kFollowing;
}

WheelCommand make_wheel_command(double v, double dv, const DriveConfig& d) {
  WheelCommand c;
  c.v_m_s = v;
  c.dv_m_s = dv;
  c.left_m_s = v - dv / 2;  // seed 000: v_l = v - dv/2, v_r = v + dv/2
  c.right_m_s = v + dv / 2;
  const double to_motor = d.gear_ratio / (M_PI * d.wheel_diameter_m);  // w = v k / (pi D)
  c.left_motor_rev_s = c.left_m_s * to_motor;
  c.right_motor_rev_s = c.right_m_s * to_motor;
  return c;
}

void Trail::add(const Eigen::Vector2d& p) {
  if (!p.allFinite()) return;
  if (points_.empty() || (p - points_.back()).norm() >= spacing_m_) points_.push_back(p);
}

void Trail::update_progress(const Eigen::Vector2d& p) {
  if (points_.size() < 2) return;
  // The segment nearest to the mower within a forward window; progress never moves back, so a
  // trail that passes near itself (a stop, a detour) is followed in the walked order.
  constexpr std::size_t kWindow = 40;
  double best = std::numeric_limits<double>::infinity();
  std::size_t best_i = progress_;
  const std::size_t end = std::min(points_.size() - 1, progress_ + kWindow);
  for (std::size_t i = progress_; i < end; ++i) {
    const Eigen::Vector2d a = points_[i], ab = points_[i + 1] - a;
    const double l2 = ab.squaredNorm();
    const double t = l2 > 0 ? std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
    const double d = (p - (a + t * ab)).norm();
    if (d < best) {
      best = d;
      best_i = i;
    }
  }
  progress_ = best_i;
}

Trail::Projection Trail::project(const Eigen::Vector2d& p, std::size_t window) const {
  Projection best;
  if (points_.size() < 2) return best;
  double best_d = std::numeric_limits<double>::infinity();
  double along = 0;
  const std::size_t begin = std::min(progress_, points_.size() - 2);
  const std::size_t end = std::min(points_.size() - 1, begin + window);
  for (std::size_t i = begin; i < end; ++i) {
    const Eigen::Vector2d a = points_[i], b = points_[i + 1];
    const Eigen::Vector2d seg = b - a;
    const double len = seg.norm();
    if (len < 1e-9) continue;
    const Eigen::Vector2d u = seg / len;
    // The first segment extends backwards, the last forwards, so points beyond the ends project.
    double s = (p - a).dot(u);
    if (i + 1 < end) s = std::min(s, len);
    if (i > begin) s = std::max(s, 0.0);
    const Eigen::Vector2d q = a + s * u;
    const double d = (p - q).norm();
    // Ties (a point beyond a corner is equally near the end of one segment and the start of the
    // next) go to the later segment: its direction is where the trail goes on. The lateral error
    // is the full distance, so a pose beyond a corner is never "on the trail".
    if (d <= best_d) {
      best_d = d;
      const Eigen::Vector2d r = p - q;
      const double side = u.x() * r.y() - u.y() * r.x();
      best.lateral_m = side >= 0 ? d : -d;
      best.heading_rad = std::atan2(u.y(), u.x());
      best.along_m = along + s;
      best.valid = true;
    }
    along += len;
  }
  return best;
}

Pose2 predict_pose(const Pose2& p, double v, double dv, double b, double dt) {
  const double w = dv / b;
  Pose2 out;
  out.yaw_rad = p.yaw_rad + w * dt;
  if (std::abs(w) < 1e-9) {
    out.x_m = p.x_m + v * dt * std::cos(p.yaw_rad);
    out.y_m = p.y_m + v * dt * std::sin(p.yaw_rad);
  } else {  // exact arc of the unicycle
    out.x_m = p.x_m + v / w * (std::sin(out.yaw_rad) - std::sin(p.yaw_rad));
    out.y_m = p.y_m - v / w * (std::cos(out.yaw_rad) - std::cos(p.yaw_rad));
  }
  return out;
}

double choose_dv(const Pose2& pose, double v, const Trail& trail, const DriveConfig& d) {
  const int n = std::max(d.dv_samples, 3) | 1;  // odd: dv = 0 is a candidate
  auto cost = [&](double dv) {
    const Pose2 q = predict_pose(pose, v, dv, d.track_width_m, d.prediction_s);
    const auto pr = trail.project(q.xy());
    if (!pr.valid) return std::numeric_limits<double>::infinity();
    const double e_p = pr.lateral_m;                              // lateral error
    const double e_fai = wrap_angle(q.yaw_rad - pr.heading_rad);  // heading error
    return std::pow(d.lateral_weight * e_p, 2) + e_fai * e_fai;   // seed 000: (k e_p)^2 + e_fai^2
  };
  const double step = 2 * d.max_dv_m_s / (n - 1);
  int best = n / 2;
  std::vector<double> costs(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    costs[std::size_t(i)] = cost(-d.max_dv_m_s + i * step);
    if (costs[std::size_t(i)] < costs[std::size_t(best)]) best = i;
  }
  double dv = -d.max_dv_m_s + best * step;
  if (best > 0 && best < n - 1) {  // parabola through the best sample and its neighbours
    const double c0 = costs[std::size_t(best - 1)], c1 = costs[std::size_t(best)],
                 c2 = costs[std::size_t(best + 1)];
    const double den = c0 - 2 * c1 + c2;
    if (den > 1e-12 && std::isfinite(den)) dv += 0.5 * step * (c0 - c2) / den;
  }
  return std::clamp(dv, -d.max_dv_m_s, d.max_dv_m_s);
}

FollowController::FollowController(const DriveConfig& drive, const SafetyConfig& safety)
    : drive_(drive), safety_(safety) {}

FollowController::Output FollowController::step(const Pose2& mower,
                                                const std::optional<Eigen::Vector2d>& target,
                                                Trail& trail, double dt) {
  Output out;
  out.state = check_safety(target, safety_);
  if (target) out.distance_m = target->norm();
  if (out.state != FollowState::kFollowing || trail.points().size() < 2) {
    // seed 000, step 6: both wheel speeds 0 at once (no ramp).
    v_ = dv_ = 0;
    out.command = make_wheel_command(0, 0, drive_);
    return out;
  }
  trail.update_progress(mower.xy());
  const auto here = trail.project(mower.xy());
  // Speed from the distance to keep, slowed while the mower is turned away from the trail.
  double v_des = std::clamp(drive_.speed_gain_1_s * (out.distance_m - drive_.follow_distance_m),
                            0.0, drive_.max_speed_m_s);
  const bool hold = v_des <= 0.0;  // close enough: stand still rather than turn in place
  if (here.valid) v_des *= std::max(0.0, std::cos(wrap_angle(mower.yaw_rad - here.heading_rad)));
  // Slow down before a corner: the trail's direction one prediction horizon ahead differs.
  const auto ahead =
      trail.project(predict_pose(mower, v_, 0.0, drive_.track_width_m, drive_.prediction_s).xy());
  if (here.valid && ahead.valid)
    v_des *= std::max(0.3, std::cos(wrap_angle(ahead.heading_rad - here.heading_rad)));
  const double dv_acc = drive_.max_accel_m_s2 * dt;
  double v = std::clamp(v_des, v_ - dv_acc, v_ + dv_acc);
  double dv = hold ? 0.0 : choose_dv(mower, v, trail, drive_);
  const double ddv = drive_.max_dv_rate_m_s2 * dt;
  dv = std::clamp(dv, dv_ - ddv, dv_ + ddv);
  // Wheel speed limit: scale v so that |v| + |dv|/2 fits, keeping the turn.
  if (std::abs(v) + std::abs(dv) / 2 > drive_.max_wheel_speed_m_s)
    v = std::max(0.0, drive_.max_wheel_speed_m_s - std::abs(dv) / 2);
  v_ = v;
  dv_ = dv;
  out.command = make_wheel_command(v, dv, drive_);
  return out;
}

}  // namespace fieldlidar::follow
