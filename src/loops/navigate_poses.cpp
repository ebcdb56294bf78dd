// The navigate loop's pose: the truth, or LiDAR odometry at each mapped sweep carried between
// sweeps by the commanded speeds.
#include "fieldlidar/loops/navigate_poses.hpp"

#include <algorithm>

#include "fieldlidar/planning/path_follower.hpp"
#include "fieldlidar/sim/motion.hpp"

namespace fieldlidar::loops {

NavigatePoses::NavigatePoses(const sim::Scene& scene, const SensorModel& sensor,
                             const planning::Pose2& start,
                             std::optional<odometry::OdometryConfig> odometry,
                             const MotionStreamsConfig& streams, double lidar_pitch_rad)
    : scene_(scene), lidar_pitch_rad_(lidar_pitch_rad), estimate_(start) {
  if (odometry) odometry_.emplace(sensor, scene.sensor_height_m(), *odometry, streams);
}

Pose NavigatePoses::lidar_pose(const planning::Pose2& p) const {
  return sim::pose_on_ground(scene_, {p.x_m, p.y_m}, p.yaw_rad) *
         Eigen::Translation3d(0, 0, scene_.sensor_height_m()) *
         Eigen::AngleAxisd(lidar_pitch_rad_, Eigen::Vector3d::UnitY());
}

Pose NavigatePoses::base_at(double t_s) const {
  // The period holding t_s (the last one before it; the first for earlier times).
  auto it = std::upper_bound(periods_.begin(), periods_.end(), t_s,
                             [](double t, const Period& p) { return t < p.t0_s; });
  if (it != periods_.begin()) --it;
  const Period& p = *it;
  const planning::Pose2 q =
      planning::integrate_unicycle(p.start, p.v_m_s, p.yaw_rate_rad_s, std::max(0.0, t_s - p.t0_s));
  return sim::pose_on_ground(scene_, {q.x_m, q.y_m}, q.yaw_rad);
}

Pose NavigatePoses::place_sweep(const PointCloud& sweep, double t_s, const planning::Pose2& truth) {
  const Pose T_true = lidar_pose(truth);
  if (!odometry_) {
    estimate_ = truth;
    return T_true;
  }
  if (sweeps_ == 0) {
    T_world_odom_ = T_true;  // the odometry's frame: the first sweep's lidar pose
  } else if (!periods_.empty()) {
    odometry_->add_streams([this](double t) { return base_at(t); }, last_sweep_t_, t_s);
  }
  const auto r = odometry_->register_sweep(sweep);
  unregistered_ += sweeps_ > 0 && !r.registered;
  ++sweeps_;
  last_sweep_t_ = t_s;
  const Pose T_est = T_world_odom_ * r.T_world_lidar;
  const Eigen::Vector3d x = T_est.rotation().col(0);
  estimate_ = {T_est.translation().x(), T_est.translation().y(), std::atan2(x.y(), x.x())};
  return T_est;
}

void NavigatePoses::advance(const planning::Pose2& truth_before, double v_m_s,
                            double yaw_rate_rad_s, double dt_s) {
  if (odometry_) periods_.push_back({t_now_, truth_before, v_m_s, yaw_rate_rad_s});
  t_now_ += dt_s;
  estimate_ = planning::integrate_unicycle(estimate_, v_m_s, yaw_rate_rad_s, dt_s);
}

}  // namespace fieldlidar::loops
