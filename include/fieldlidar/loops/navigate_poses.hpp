#pragma once
/// \file Where the navigate loop's robot takes its pose from: the simulator's truth, or its own
/// estimate: LiDAR odometry (with the IMU and wheel streams recorded while it drives) at every
/// mapped sweep, carried between sweeps by the commanded speeds. The odometry's frame is placed in
/// the map by the true start pose (the robot is told where it starts). Map frame, m, s, rad.

#include <optional>
#include <vector>

#include "fieldlidar/core/point_cloud.hpp"
#include "fieldlidar/core/pose.hpp"
#include "fieldlidar/loops/pose_source.hpp"
#include "fieldlidar/planning/pose2.hpp"
#include "fieldlidar/sim/scene.hpp"

namespace fieldlidar::loops {

class NavigatePoses {
 public:
  /// `odometry`: nullopt for the truth.
  NavigatePoses(const sim::Scene& scene, const SensorModel& sensor, const planning::Pose2& start,
                std::optional<odometry::OdometryConfig> odometry,
                const MotionStreamsConfig& streams, double lidar_pitch_rad = 0.0);

  /// The pose the robot believes (the truth without odometry).
  const planning::Pose2& estimate() const { return estimate_; }
  /// The true lidar pose at the base pose `truth` (on the scene's ground).
  Pose lidar_pose(const planning::Pose2& truth) const;
  /// A sweep taken at t_s from the true base pose: the lidar pose the map places it by (the
  /// truth, or the odometry's registration of it after the streams since the last sweep).
  Pose place_sweep(const PointCloud& sweep, double t_s, const planning::Pose2& truth);
  /// One control period driven: the true motion is recorded (for the streams) and the estimate
  /// carried by the commanded speeds.
  void advance(const planning::Pose2& truth_before, double v_m_s, double yaw_rate_rad_s,
               double dt_s);
  bool odometry() const { return odometry_.has_value(); }
  std::size_t unregistered() const { return unregistered_; }

 private:
  struct Period {
    double t0_s;
    planning::Pose2 start;
    double v_m_s, yaw_rate_rad_s;
  };
  Pose base_at(double t_s) const;

  const sim::Scene& scene_;
  double lidar_pitch_rad_ = 0;  ///< the mount's pitch (positive: nose down)
  std::optional<OdometryPoseSource> odometry_;
  planning::Pose2 estimate_;
  Pose T_world_odom_ = Pose::Identity();
  std::vector<Period> periods_;  ///< true motion since the start
  double t_now_ = 0, last_sweep_t_ = -1;
  std::size_t sweeps_ = 0, unregistered_ = 0;
};

}  // namespace fieldlidar::loops
