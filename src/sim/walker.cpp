#include "fieldlidar/sim/walker.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace fieldlidar::sim {

namespace {
constexpr double kKneeHeightM = 0.45;  // legs_m truth height (m above ground)
}

Walker::Walker(WalkerConfig config) : config_(std::move(config)) {
  if (config_.path_m.size() < 2) throw std::invalid_argument("Walker: path needs >= 2 points");
  if (config_.speed.empty()) throw std::invalid_argument("Walker: speed schedule is empty");
  std::sort(config_.speed.begin(), config_.speed.end(),
            [](const SpeedPhase& a, const SpeedPhase& b) { return a.t_start_s < b.t_start_s; });
  cumulative_.push_back(0.0);
  const auto& p = config_.path_m;
  for (std::size_t i = 1; i < p.size(); ++i)
    cumulative_.push_back(cumulative_.back() + (p[i] - p[i - 1]).norm());
  if (config_.closed) cumulative_.push_back(cumulative_.back() + (p.front() - p.back()).norm());
  if (!(cumulative_.back() > 0)) throw std::invalid_argument("Walker: path has zero length");
}

double Walker::arc_length_at(double t_s) const {
  const auto& ph = config_.speed;
  double s = config_.start_offset_m;
  if (t_s <= 0) return s + ph.front().speed_m_s * t_s;
  for (std::size_t k = 0; k < ph.size(); ++k) {
    const double a = k == 0 ? 0.0 : std::max(0.0, ph[k].t_start_s);
    const double b = k + 1 < ph.size() ? ph[k + 1].t_start_s : t_s;
    const double hi = std::min(b, t_s);
    if (hi > a) s += ph[k].speed_m_s * (hi - a);
    if (b >= t_s) break;
  }
  if (!config_.closed) s = std::clamp(s, 0.0, path_length_m());
  return s;
}

double Walker::speed_at(double t_s) const {
  double v = config_.speed.front().speed_m_s;
  for (const auto& p : config_.speed)
    if (p.t_start_s <= t_s) v = p.speed_m_s;
  if (!config_.closed) {
    const double s = arc_length_at(t_s);
    if (s >= path_length_m() || s <= 0.0) v = 0.0;
  }
  return v;
}

void Walker::path_point(double s_m, Eigen::Vector2d& xy_m, Eigen::Vector2d& dir) const {
  const double total = path_length_m();
  double s = config_.closed ? std::fmod(s_m, total) : std::clamp(s_m, 0.0, total);
  if (s < 0) s += total;
  auto it = std::upper_bound(cumulative_.begin(), cumulative_.end(), s);
  std::size_t seg = it == cumulative_.begin() ? 0 : std::size_t(it - cumulative_.begin()) - 1;
  seg = std::min(seg, cumulative_.size() - 2);
  const auto& p = config_.path_m;
  const Eigen::Vector2d a = p[seg];
  const Eigen::Vector2d b = p[(seg + 1) % p.size()];
  const double len = cumulative_[seg + 1] - cumulative_[seg];
  const double u = len > 0 ? (s - cumulative_[seg]) / len : 0.0;
  xy_m = a + u * (b - a);
  dir = len > 0 ? Eigen::Vector2d((b - a) / len) : Eigen::Vector2d::UnitX();
}

double Walker::foot_offset(int leg, double t_s) const {
  // Feet swing fore and aft in anti-phase; the gait phase advances with the distance walked, so
  // a standing person has both feet under the hips.
  const double s = arc_length_at(t_s);
  const double phase = 2 * std::numbers::pi * s / config_.stride_m + leg * std::numbers::pi;
  const double amplitude = 0.25 * config_.stride_m * std::min(1.0, speed_at(t_s) / 0.6);
  return amplitude * std::sin(phase);
}

PersonTruth Walker::truth_at(double t_s) const {
  PersonTruth p;
  p.id = config_.id;
  const double s = arc_length_at(t_s);
  Eigen::Vector2d xy, dir;
  path_point(s, xy, dir);
  p.position_m = xy;
  p.velocity_m_s = speed_at(t_s) * dir;
  p.heading_rad = std::atan2(dir.y(), dir.x());
  p.path_length_m = s;
  const Eigen::Vector2d lateral(-dir.y(), dir.x());
  const double hip_h = 0.53 * config_.height_m;
  const double u = (kKneeHeightM - config_.leg_radius_m) / (hip_h - config_.leg_radius_m);
  for (int k = 0; k < 2; ++k) {
    const double side = k == 0 ? 0.5 : -0.5;
    const Eigen::Vector2d hip = xy + side * config_.hip_width_m * lateral;
    const Eigen::Vector2d foot = hip + foot_offset(k, t_s) * dir;
    p.legs_m[k] = foot + u * (hip - foot);
  }
  return p;
}

PersonBody Walker::body_at(double t_s, double ground_z_m) const {
  PersonBody body;
  body.id = config_.id;
  Eigen::Vector2d xy, dir;
  path_point(arc_length_at(t_s), xy, dir);
  const Eigen::Vector2d lateral(-dir.y(), dir.x());
  const double h = config_.height_m;
  const double hip_h = 0.53 * h;
  for (int k = 0; k < 2; ++k) {
    const double side = k == 0 ? 0.5 : -0.5;
    const Eigen::Vector2d hip = xy + side * config_.hip_width_m * lateral;
    const Eigen::Vector2d foot = hip + foot_offset(k, t_s) * dir;
    body.parts[k] = {Eigen::Vector3d(foot.x(), foot.y(), ground_z_m + config_.leg_radius_m),
                     Eigen::Vector3d(hip.x(), hip.y(), ground_z_m + hip_h), config_.leg_radius_m};
  }
  body.parts[2] = {Eigen::Vector3d(xy.x(), xy.y(), ground_z_m + hip_h + 0.1),
                   Eigen::Vector3d(xy.x(), xy.y(), ground_z_m + 0.8 * h - 0.05),
                   config_.torso_radius_m};
  const Eigen::Vector3d head(xy.x(), xy.y(), ground_z_m + 0.93 * h);
  body.parts[3] = {head, head, 0.1};
  body.bound_center_m = Eigen::Vector3d(xy.x(), xy.y(), ground_z_m + 0.5 * h);
  body.bound_radius_m = 0.5 * h + 0.1 + 0.3 * config_.stride_m;
  return body;
}

}  // namespace fieldlidar::sim
