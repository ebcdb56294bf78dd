#include "fieldlidar/sim/motion.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>

#include "fieldlidar/core/pose2.hpp"

namespace fieldlidar::sim {

namespace {

/// A polyline parameterised by unwrapped arc length (wraps when closed, clamps when open).
class Route {
 public:
  Route(std::span<const Eigen::Vector2d> pts, bool closed)
      : pts_(pts.begin(), pts.end()), closed_(closed) {
    if (pts_.size() < 2) throw std::invalid_argument("route needs at least 2 waypoints");
    cum_.push_back(0);
    for (std::size_t i = 1; i < pts_.size(); ++i)
      cum_.push_back(cum_.back() + (pts_[i] - pts_[i - 1]).norm());
    if (closed_) cum_.push_back(cum_.back() + (pts_.front() - pts_.back()).norm());
    if (!(cum_.back() > 0)) throw std::invalid_argument("route has zero length");
  }
  double length() const { return cum_.back(); }
  bool closed() const { return closed_; }
  Eigen::Vector2d at(double s) const {
    const double total = length();
    s = closed_ ? std::fmod(s, total) : std::clamp(s, 0.0, total);
    if (s < 0) s += total;
    auto it = std::upper_bound(cum_.begin(), cum_.end(), s);
    std::size_t seg = it == cum_.begin() ? 0 : std::size_t(it - cum_.begin()) - 1;
    seg = std::min(seg, cum_.size() - 2);
    const Eigen::Vector2d a = pts_[seg], b = pts_[(seg + 1) % pts_.size()];
    const double len = cum_[seg + 1] - cum_[seg];
    return len > 0 ? Eigen::Vector2d(a + (s - cum_[seg]) / len * (b - a)) : a;
  }
  /// Arc length of the route point nearest to xy, searched in [s_from, s_to] every 5 cm.
  double project(const Eigen::Vector2d& xy, double s_from, double s_to) const {
    double best_s = s_from, best = 1e300;
    for (double s = s_from; s <= s_to; s += 0.05) {
      const double d = (at(s) - xy).squaredNorm();
      if (d < best) best = d, best_s = s;
    }
    return best_s;
  }

 private:
  std::vector<Eigen::Vector2d> pts_;
  bool closed_;
  std::vector<double> cum_;
};

/// Pure pursuit with speed, acceleration and yaw-rate limits; `target_speed(t, s)` caps the speed
/// at time t and route progress s.
RobotMotion drive(const Scene& scene, const Route& route, double duration_s, const DriveConfig& cfg,
                  const std::function<double(double, double)>& target_speed) {
  if (!(duration_s > 0) || !(cfg.rate_hz > 0))
    throw std::invalid_argument("drive: bad duration or rate");
  const double dt = 1.0 / cfg.rate_hz;
  Eigen::Vector2d xy = route.at(0.0);
  const Eigen::Vector2d d0 = route.at(0.2) - xy;
  double yaw = std::atan2(d0.y(), d0.x());
  double v = 0, w = 0, s = 0;
  Trajectory base;
  const int steps = static_cast<int>(std::ceil(duration_s * cfg.rate_hz));
  for (int k = 0; k <= steps; ++k) {
    const double t = k * dt;
    base.push_back(t, pose_on_ground(scene, xy, yaw, cfg.wheel_base_m, cfg.track_width_m));
    s = std::max(s, route.project(xy, s - 0.5, s + 3.0));
    const Eigen::Vector2d target = route.at(s + cfg.lookahead_m);
    const Eigen::Vector2d rel = target - xy;
    const double bearing = wrap_angle(std::atan2(rel.y(), rel.x()) - yaw);
    const double dist = std::max(rel.norm(), 1e-3);
    const double curvature = 2 * std::sin(bearing) / dist;
    double v_des = std::clamp(target_speed(t, s), 0.0, cfg.speed_m_s);
    if (!route.closed())
      v_des =
          std::min(v_des, std::sqrt(2 * cfg.max_accel_m_s2 * std::max(0.0, route.length() - s)));
    if (std::abs(curvature) > 1e-6)
      v_des = std::min(v_des, cfg.max_yaw_rate_rad_s / std::abs(curvature));
    double w_des = v * curvature;
    if (std::abs(bearing) > 1.0) {  // target far to the side or behind: turn on the spot first
      v_des = 0;
      w_des = std::clamp(2.0 * bearing, -cfg.max_yaw_rate_rad_s, cfg.max_yaw_rate_rad_s);
    }
    v += std::clamp(v_des - v, -cfg.max_accel_m_s2 * dt, cfg.max_accel_m_s2 * dt);
    w += std::clamp(w_des - w, -cfg.max_yaw_accel_rad_s2 * dt, cfg.max_yaw_accel_rad_s2 * dt);
    w = std::clamp(w, -cfg.max_yaw_rate_rad_s, cfg.max_yaw_rate_rad_s);
    // Exact arc integration of the unicycle over one step.
    const double yaw_mid = yaw + 0.5 * w * dt;
    xy += v * dt * Eigen::Vector2d(std::cos(yaw_mid), std::sin(yaw_mid));
    yaw = wrap_angle(yaw + w * dt);
  }
  const double h = cfg.sensor_height_m >= 0 ? cfg.sensor_height_m : scene.sensor_height_m();
  Pose T_base_lidar = Pose::Identity();
  T_base_lidar.translation() = Eigen::Vector3d(0, 0, h);
  return RobotMotion(std::move(base), T_base_lidar);
}

}  // namespace

RobotMotion::RobotMotion(Trajectory base, Pose T_base_lidar)
    : base_(std::move(base)), T_base_lidar_(T_base_lidar) {
  if (base_.empty()) throw std::invalid_argument("RobotMotion: empty trajectory");
}

Pose RobotMotion::T_world_base(double t_s) const {
  const double t = std::clamp(t_s, start_s(), end_s());
  return *base_.at(t);
}

Pose RobotMotion::T_world_lidar(double t_s) const {
  return T_world_base(t_s) * T_base_lidar_;
}

std::function<Pose(double)> RobotMotion::lidar_pose_fn() const {
  return [this](double t) { return T_world_lidar(t); };
}
std::function<Pose(double)> RobotMotion::base_pose_fn() const {
  return [this](double t) { return T_world_base(t); };
}

Pose pose_on_ground(const Scene& scene, const Eigen::Vector2d& xy_m, double yaw_rad,
                    double wheel_base_m, double track_width_m) {
  const Eigen::Vector2d fwd(std::cos(yaw_rad), std::sin(yaw_rad));
  const Eigen::Vector2d left(-fwd.y(), fwd.x());
  const double hf = scene.ground_height_at(xy_m + 0.5 * wheel_base_m * fwd);
  const double hb = scene.ground_height_at(xy_m - 0.5 * wheel_base_m * fwd);
  const double hl = scene.ground_height_at(xy_m + 0.5 * track_width_m * left);
  const double hr = scene.ground_height_at(xy_m - 0.5 * track_width_m * left);
  // Rz(yaw) Ry(pitch) Rx(roll): a positive pitch lowers the nose, a positive roll raises the left.
  const double pitch = -std::atan2(hf - hb, wheel_base_m);
  const double roll = std::atan2(hl - hr, track_width_m);
  const double z = 0.25 * (hf + hb + hl + hr);
  return make_pose(xy_m.x(), xy_m.y(), z, roll, pitch, yaw_rad);
}

RobotMotion drive_route(const Scene& scene, std::span<const Eigen::Vector2d> route_m, bool closed,
                        double duration_s, const DriveConfig& config) {
  const Route route(route_m, closed);
  return drive(scene, route, duration_s, config, [&](double, double) { return config.speed_m_s; });
}

RobotMotion drive_scene_route(const Scene& scene, double duration_s, DriveConfig config) {
  if (scene.robot_route().size() < 2) throw std::invalid_argument("scene has no robot route");
  config.speed_m_s = scene.robot_speed_m_s();
  return drive_route(scene, scene.robot_route(), scene.robot_route_closed(), duration_s, config);
}

RobotMotion timed_route(const Scene& scene, std::span<const TimedWaypoint> waypoints,
                        const DriveConfig& config) {
  if (waypoints.size() < 2) throw std::invalid_argument("timed_route: needs at least 2 waypoints");
  for (std::size_t i = 1; i < waypoints.size(); ++i)
    if (!(waypoints[i].stamp_s > waypoints[i - 1].stamp_s))
      throw std::invalid_argument("timed_route: waypoint times must increase (waypoint " +
                                  std::to_string(i) + ")");
  const double dt = 1.0 / config.rate_hz;
  Trajectory base;
  std::size_t seg = 0;
  double yaw = 0.0;
  // Initial heading: towards the first waypoint that is elsewhere.
  for (std::size_t i = 1; i < waypoints.size(); ++i) {
    const Eigen::Vector2d d = waypoints[i].xy_m - waypoints[0].xy_m;
    if (d.norm() > 1e-6) {
      yaw = std::atan2(d.y(), d.x());
      break;
    }
  }
  const double t0 = waypoints.front().stamp_s, t1 = waypoints.back().stamp_s;
  const int steps = static_cast<int>(std::ceil((t1 - t0) / dt));
  for (int k = 0; k <= steps; ++k) {
    const double t = std::min(t0 + k * dt, t1);
    while (seg + 2 < waypoints.size() && t > waypoints[seg + 1].stamp_s) ++seg;
    const auto& a = waypoints[seg];
    const auto& b = waypoints[seg + 1];
    const double u = std::clamp((t - a.stamp_s) / (b.stamp_s - a.stamp_s), 0.0, 1.0);
    const Eigen::Vector2d d = b.xy_m - a.xy_m;
    if (d.norm() > 1e-6) yaw = std::atan2(d.y(), d.x());
    if (k > 0 && t <= base.poses().back().stamp_s) break;
    base.push_back(
        t, pose_on_ground(scene, a.xy_m + u * d, yaw, config.wheel_base_m, config.track_width_m));
  }
  const double h = config.sensor_height_m >= 0 ? config.sensor_height_m : scene.sensor_height_m();
  Pose T_base_lidar = Pose::Identity();
  T_base_lidar.translation() = Eigen::Vector3d(0, 0, h);
  return RobotMotion(std::move(base), T_base_lidar);
}

RobotMotion follow_operator(const Scene& scene, std::uint16_t person_id, double duration_s,
                            const DriveConfig& config) {
  const Walker* op = nullptr;
  for (const auto& w : scene.walkers())
    if (w.id() == person_id) op = &w;
  if (!op)
    throw std::invalid_argument("follow_operator: no person with id " + std::to_string(person_id));
  const Route route(op->config().path_m, op->config().closed);
  DriveConfig cfg = config;
  cfg.speed_m_s = std::max(config.speed_m_s, 1.6);  // a mower's top speed
  const double lag = config.follow_lag_m;
  // Keep `lag` behind along the path: speed proportional to the gap error (1/s gain).
  return drive(scene, route, duration_s, cfg, [op, lag](double t, double s) {
    return 1.0 * (op->arc_length_at(t) - lag - s) + op->speed_at(t);
  });
}

std::vector<ImuSample> simulate_imu(const std::function<Pose(double)>& T_world_imu, double t0_s,
                                    double t1_s, const ImuConfig& cfg) {
  if (!(cfg.rate_hz > 0)) throw std::invalid_argument("ImuConfig.rate_hz must be > 0");
  std::mt19937_64 rng(cfg.seed);
  std::normal_distribution<double> n01(0.0, 1.0);
  const Eigen::Vector3d gyro_bias(cfg.gyro_bias_sigma_rad_s * n01(rng),
                                  cfg.gyro_bias_sigma_rad_s * n01(rng),
                                  cfg.gyro_bias_sigma_rad_s * n01(rng));
  const Eigen::Vector3d accel_bias(cfg.accel_bias_sigma_m_s2 * n01(rng),
                                   cfg.accel_bias_sigma_m_s2 * n01(rng),
                                   cfg.accel_bias_sigma_m_s2 * n01(rng));
  std::vector<ImuSample> out;
  const double dt = 1.0 / cfg.rate_hz;
  // Central differences: 5 ms for the rate, 10 ms for the acceleration (the true trajectory is
  // sampled at 200 Hz and linearly interpolated in between).
  const double hg = 0.005, ha = 0.01;
  for (double t = t0_s; t <= t1_s + 1e-9; t += dt) {
    const Pose T = T_world_imu(t);
    const Eigen::Matrix3d dR =
        T_world_imu(t - hg).linear().transpose() * T_world_imu(t + hg).linear();
    const Eigen::AngleAxisd aa(dR);
    const Eigen::Vector3d omega = aa.axis() * aa.angle() / (2 * hg);
    const Eigen::Vector3d acc_world = (T_world_imu(t + ha).translation() - 2 * T.translation() +
                                       T_world_imu(t - ha).translation()) /
                                      (ha * ha);
    ImuSample s;
    s.stamp_s = t;
    s.gyro_rad_s =
        omega + gyro_bias + cfg.gyro_noise_rad_s * Eigen::Vector3d(n01(rng), n01(rng), n01(rng));
    s.accel_m_s2 = T.linear().transpose() * (acc_world + Eigen::Vector3d(0, 0, cfg.gravity_m_s2)) +
                   accel_bias +
                   cfg.accel_noise_m_s2 * Eigen::Vector3d(n01(rng), n01(rng), n01(rng));
    out.push_back(s);
  }
  return out;
}

std::vector<WheelOdometrySample> simulate_wheel_odometry(
    const std::function<Pose(double)>& T_world_base, double t0_s, double t1_s,
    const WheelOdometryConfig& cfg) {
  if (!(cfg.rate_hz > 0) || !(cfg.track_width_m > 0) || !(cfg.wheel_radius_m > 0))
    throw std::invalid_argument(
        "WheelOdometryConfig: rate, track width and wheel radius must be > 0");
  std::mt19937_64 rng(cfg.seed);
  std::normal_distribution<double> n01(0.0, 1.0);
  std::vector<WheelOdometrySample> out;
  const double dt = 1.0 / cfg.rate_hz, h = 0.005;
  const Pose T0 = T_world_base(t0_s);
  double x = T0.translation().x(), y = T0.translation().y(), yaw = yaw_of(T0);
  for (double t = t0_s; t <= t1_s + 1e-9; t += dt) {
    const Pose Ta = T_world_base(t - h), Tb = T_world_base(t + h);
    const Eigen::Vector3d v_body =
        T_world_base(t).linear().transpose() * (Tb.translation() - Ta.translation()) / (2 * h);
    const Eigen::AngleAxisd aa(Ta.linear().transpose() * Tb.linear());
    const double w = (aa.axis() * aa.angle()).z() / (2 * h);
    const auto noisy = [&](double speed) {
      return speed * (1.0 + cfg.slip_sigma * n01(rng)) + cfg.noise_m_s * n01(rng);
    };
    WheelOdometrySample s;
    s.stamp_s = t;
    s.left_m_s = noisy(v_body.x() - 0.5 * w * cfg.track_width_m);
    s.right_m_s = noisy(v_body.x() + 0.5 * w * cfg.track_width_m);
    s.left_rad_s = s.left_m_s / cfg.wheel_radius_m;
    s.right_rad_s = s.right_m_s / cfg.wheel_radius_m;
    s.linear_m_s = 0.5 * (s.left_m_s + s.right_m_s);
    s.yaw_rate_rad_s = (s.right_m_s - s.left_m_s) / cfg.track_width_m;
    if (!out.empty()) {
      const double ym = yaw + 0.5 * s.yaw_rate_rad_s * dt;
      x += s.linear_m_s * dt * std::cos(ym);
      y += s.linear_m_s * dt * std::sin(ym);
      yaw = wrap_angle(yaw + s.yaw_rate_rad_s * dt);
    }
    s.dead_reckoned = make_pose(x, y, 0, 0, 0, yaw);
    out.push_back(s);
  }
  return out;
}

}  // namespace fieldlidar::sim
