#pragma once
/// \file Robot motion for the simulator: a differential-drive robot driving a route (or following
/// the lawn operator), its true poses, and the IMU and wheel-odometry streams it would record.

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "fieldlidar/core/imu_sample.hpp"
#include "fieldlidar/core/pose.hpp"
#include "fieldlidar/sim/scene.hpp"

namespace fieldlidar::sim {

struct DriveConfig {
  double speed_m_s = 1.0;  ///< cruise speed
  double max_accel_m_s2 = 0.8;
  double max_yaw_rate_rad_s = 1.0;
  double max_yaw_accel_rad_s2 = 3.0;
  double lookahead_m = 1.2;       ///< pure-pursuit look-ahead along the route
  double rate_hz = 200.0;         ///< integration / truth sample rate
  double wheel_base_m = 0.6;      ///< length used to take pitch from the ground (m)
  double track_width_m = 0.5;     ///< used to take roll from the ground (m)
  double sensor_height_m = -1.0;  ///< lidar above the base; < 0 uses Scene::sensor_height_m
  double follow_lag_m = 2.5;      ///< follow_operator: distance kept behind the operator
};

/// The robot's true motion sampled at DriveConfig::rate_hz: base poses (base frame on the ground,
/// x forward) and the lidar mounted straight above the base.
class RobotMotion {
 public:
  RobotMotion() = default;
  RobotMotion(Trajectory base, Pose T_base_lidar);
  const Trajectory& base() const { return base_; }
  const Pose& T_base_lidar() const { return T_base_lidar_; }
  double start_s() const { return base_.poses().front().stamp_s; }
  double end_s() const { return base_.poses().back().stamp_s; }
  /// Interpolated poses (clamped to the covered time span).
  Pose T_world_base(double t_s) const;
  Pose T_world_lidar(double t_s) const;
  std::function<Pose(double)> lidar_pose_fn() const;
  std::function<Pose(double)> base_pose_fn() const;

 private:
  Trajectory base_;
  Pose T_base_lidar_ = Pose::Identity();
};

/// Drives the route (pure pursuit, speed/acceleration/yaw-rate limits) over [0, duration_s];
/// the base sits on the scene's ground with pitch and roll from the terrain.
RobotMotion drive_route(const Scene& scene, std::span<const Eigen::Vector2d> route_m, bool closed,
                        double duration_s, const DriveConfig& config = {});
/// Drives the scene's own robot route at its suggested speed.
RobotMotion drive_scene_route(const Scene& scene, double duration_s, DriveConfig config = {});
/// Lawn: the mower follows walker `person_id` along the operator path, keeping follow_lag_m behind
/// (stops while the operator stands, falls behind when they walk too fast).
RobotMotion follow_operator(const Scene& scene, std::uint16_t person_id, double duration_s,
                            const DriveConfig& config = {});
/// A scripted waypoint with the time (s) the robot is there.
struct TimedWaypoint {
  double stamp_s = 0.0;
  Eigen::Vector2d xy_m = Eigen::Vector2d::Zero();
};
/// Moves through timed waypoints (increasing times), straight at constant speed between two,
/// heading along the motion (kept while standing), on the ground; sampled at config.rate_hz.
/// Throws std::invalid_argument for fewer than 2 waypoints or non-increasing times.
RobotMotion timed_route(const Scene& scene, std::span<const TimedWaypoint> waypoints,
                        const DriveConfig& config = {});
/// Pose of a robot base resting on the ground at (x, y) with heading yaw.
Pose pose_on_ground(const Scene& scene, const Eigen::Vector2d& xy_m, double yaw_rad,
                    double wheel_base_m = 0.6, double track_width_m = 0.5);

using fieldlidar::ImuSample;  // core/imu_sample.hpp

struct ImuConfig {
  double rate_hz = 200.0;           ///< 100 .. 400 typical
  double gyro_noise_rad_s = 0.003;  ///< 1-sigma white noise per sample
  double accel_noise_m_s2 = 0.03;
  double gyro_bias_sigma_rad_s = 0.005;  ///< each axis' constant bias ~ N(0, sigma)
  double accel_bias_sigma_m_s2 = 0.05;
  double gravity_m_s2 = 9.80665;
  std::uint64_t seed = 7;
};

/// IMU stream over [t0, t1] from the true base pose function (finite differences of the pose,
/// 2 ms step), with constant per-axis biases and white noise.
std::vector<ImuSample> simulate_imu(const std::function<Pose(double)>& T_world_imu, double t0_s,
                                    double t1_s, const ImuConfig& config = {});

/// Wheel odometry of a differential-drive base: wheel surface speeds (with slip), the body twist
/// they imply, and the dead-reckoned planar pose integrated from them.
struct WheelOdometrySample {
  double stamp_s = 0.0;
  double left_m_s = 0.0;  ///< left wheel surface speed
  double right_m_s = 0.0;
  double left_rad_s = 0.0;  ///< left wheel angular speed = left_m_s / wheel radius
  double right_rad_s = 0.0;
  double linear_m_s = 0.0;                ///< body forward speed from the wheels
  double yaw_rate_rad_s = 0.0;            ///< body yaw rate from the wheels
  Pose dead_reckoned = Pose::Identity();  ///< planar pose integrated from the wheels
};

struct WheelOdometryConfig {
  double rate_hz = 50.0;
  double track_width_m = 0.5;
  double wheel_radius_m = 0.1;
  double slip_sigma = 0.03;  ///< relative 1-sigma slip per wheel and sample
  double noise_m_s = 0.005;  ///< additive 1-sigma speed noise
  std::uint64_t seed = 11;
};

std::vector<WheelOdometrySample> simulate_wheel_odometry(
    const std::function<Pose(double)>& T_world_base, double t0_s, double t1_s,
    const WheelOdometryConfig& config = {});

}  // namespace fieldlidar::sim
