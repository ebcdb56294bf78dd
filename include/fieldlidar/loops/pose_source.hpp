#pragma once
/// \file Where the closed loop's mower takes its pose from: the simulator's truth, or LiDAR
/// odometry fed with each simulated sweep and the IMU and wheel samples the mower records while
/// it drives (seed 002 as the pose source of seed 000). The odometry's frame is the lidar pose of
/// the first sweep.

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include <Eigen/Core>

#include "fieldlidar/core/point_cloud.hpp"
#include "fieldlidar/core/pose.hpp"
#include "fieldlidar/core/sensor_model.hpp"
#include "fieldlidar/follow/controller.hpp"
#include "fieldlidar/odometry/lidar_odometry.hpp"
#include "fieldlidar/sim/motion.hpp"

namespace fieldlidar::loops {

enum class PoseSource {
  kOdometry,  ///< LiDAR odometry with the IMU and wheel streams (the robot's own estimate)
  kTruth,     ///< the simulator's true pose
};
std::string to_string(PoseSource s);
/// "odometry", "truth"; nullopt otherwise.
std::optional<PoseSource> pose_source_from_string(const std::string& name);

/// The mower's motion during one control period: unicycle kinematics of the commanded wheel
/// speeds from `start` at `t0_s` (world frame, m, s, rad).
struct MowerSegment {
  follow::Pose2 start;
  double t0_s = 0;
  double v_m_s = 0, dv_m_s = 0, track_width_m = 0.4;
  follow::Pose2 at(double t_s) const;
};

/// The sensor streams of the mower as the simulator records them during one control period: IMU
/// (constant per-axis biases drawn once, white noise independent per period) and wheel speeds.
struct MotionStreamsConfig {
  sim::ImuConfig imu;
  sim::WheelOdometryConfig wheels;
};

/// The mower's IMU and wheels as the simulator records them, one control period at a time:
/// the IMU's constant per-axis biases are drawn once (from the IMU seed) and added to every
/// sample; the white noise and the wheels' slip are drawn afresh for each period.
class SimulatedStreams {
 public:
  explicit SimulatedStreams(const MotionStreamsConfig& config);
  struct Period {
    std::vector<sim::ImuSample> imu;  ///< biases included
    std::vector<sim::WheelOdometrySample> wheels;
  };
  /// The samples of [t0_s, t1_s) (half a sample short of t1: the next period starts there)
  /// simulated from the true base pose function.
  Period next(const std::function<Pose(double)>& T_world_base, double t0_s, double t1_s);
  const MotionStreamsConfig& config() const { return config_; }

 private:
  MotionStreamsConfig config_;
  Eigen::Vector3d gyro_bias_rad_s_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel_bias_m_s2_ = Eigen::Vector3d::Zero();
  std::uint64_t periods_ = 0;
};

/// LiDAR odometry as the loop's pose source. Per sweep: give the streams of the period, then
/// register the sweep.
class OdometryPoseSource {
 public:
  /// `sensor_height_m`: the lidar above the base (the IMU/wheel frame), straight up.
  OdometryPoseSource(const SensorModel& sensor, double sensor_height_m,
                     odometry::OdometryConfig config, const MotionStreamsConfig& streams);

  /// IMU and wheel samples over [t0_s, t1_s) simulated from the true base pose function.
  void add_streams(const std::function<Pose(double)>& T_world_base, double t0_s, double t1_s);
  /// The sweep (points with their time offsets, stamp = sweep start) registered: the lidar pose
  /// at its start in the odometry frame.
  odometry::OdometryResult register_sweep(const PointCloud& sweep);

 private:
  odometry::LidarOdometry odometry_;
  SimulatedStreams streams_;
};

/// Wheel odometry with an IMU as the pose source of a mower that has no multi-beam LiDAR (a 2D
/// laser at leg height sees too little of an open lawn to match scans): per period the base's
/// attitude integrated from the gyro's three axes, and the wheels' forward speed carried along
/// the base's x axis (the simulated streams: slip, noise, a constant gyro bias drawn once), from
/// the start pose, the origin of the odometry frame. The gyro's bias is the mean of its readings
/// while the wheels stand still (the mower waits for its operator before it drives), subtracted
/// from then on; while they stand, the accelerometer's mean (gravity alone) levels the attitude
/// (roll and pitch; yaw kept). On bumpy ground the base pitches and rolls: the gyro's z axis is
/// then no longer the vertical, and its pitch rate times the roll turns into a false yaw rate
/// that a planar integration (yaw from the z axis alone) accumulates. Measured, 2D follow loop
/// on the rough lawn (6 cm bumps, scene seed 0): odometry ATE 0.470 -> 0.036 m; on the level lawn
/// unchanged.
class DeadReckoningPoseSource {
 public:
  explicit DeadReckoningPoseSource(const MotionStreamsConfig& streams);
  /// Integrates the streams of [t0_s, t1_s) simulated from the true base pose function; the
  /// base's planar pose at t1_s in the odometry frame.
  follow::Pose2 advance(const std::function<Pose(double)>& T_world_base, double t0_s, double t1_s);
  const follow::Pose2& pose() const { return pose_; }

 private:
  SimulatedStreams streams_;
  Eigen::Vector3d still_gyro_sum_ = Eigen::Vector3d::Zero();  ///< gyro readings while still
  std::size_t still_samples_ = 0;
  follow::Pose2 pose_;
  /// The base's attitude in the odometry frame (rotation only; yaw = pose_.yaw_rad), levelled
  /// while still.
  Pose attitude_ = Pose::Identity();
  bool levelled_ = false;  ///< the accelerometer has levelled the attitude once
};

}  // namespace fieldlidar::loops
