#pragma once
/// \file The follow pipeline in closed loop with the simulator: each frame the mower's true pose
/// gives the sensor pose, the simulator scans, the pipeline perceives (at the pose its source
/// gives: LiDAR odometry by default, or the truth) and commands the wheels, and the mower moves by
/// unicycle kinematics of the commanded wheel speeds. m, s, rad.
///
/// Frames: the pipeline works in its recording frame, the odometry's (the lidar pose of the first
/// sweep) or, with true poses, the world. Every position of the result (true ones included) is in
/// the recording frame; `T_world_frame` places it in the world (the lawn scene).

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "fieldlidar/core/pose.hpp"
#include "fieldlidar/core/sensor_model.hpp"
#include "fieldlidar/core/trajectory_metrics.hpp"
#include "fieldlidar/follow/pipeline.hpp"
#include "fieldlidar/loops/pose_source.hpp"
#include "fieldlidar/odometry/lidar_odometry.hpp"
#include "fieldlidar/people/legs_2d_pipeline.hpp"
#include "fieldlidar/sim/scene.hpp"
#include "fieldlidar/sim/scenes.hpp"

namespace fieldlidar::loops {

/// kStandingStart: the operator stands still 2 m in front of the mower for 5 s, then walks off.
/// kRough: the default walk over rough ground (sim::LawnConfig::roughness_m 0.06 m): the mower,
/// resting on its wheels, pitches and rolls by up to ~5 deg, and so does its sensor.
enum class Scenario { kDefault, kCrossing, kStop, kFast, kOccluded, kStandingStart, kRough };
std::string to_string(Scenario s);
/// "default", "crossing", "stop", "fast", "occluded", "standing-start", "rough"; nullopt
/// otherwise.
std::optional<Scenario> scenario_from_string(const std::string& name);
/// The lawn scene options of a scenario.
sim::LawnConfig lawn_config(Scenario s);

struct ClosedLoopConfig {
  follow::FollowConfig follow;
  double max_time_s = 0;        ///< 0: 1.6 x the operator's lap time + 20 s
  double stop_fraction = 0.85;  ///< the stop command comes once this share of the loop is recorded
  double stop_radius_m = 0.4;   ///< ... and the mower is back within this of the boundary start
  std::uint64_t sim_seed = 1;   ///< sensor noise seed
  std::uint16_t operator_id = 1;  ///< the simulated person who walks the boundary
  PoseSource pose_source = PoseSource::kOdometry;
  /// The odometry's settings (its lidar-to-base mount and sweep period are set from the scene
  /// and the sensor).
  odometry::OdometryConfig odometry;
  MotionStreamsConfig streams;  ///< the IMU and wheel streams given to the odometry
  /// A planar 2D laser (SensorModel::Kind::kPlanar2D) is perceived by the 2D leg pipeline (the
  /// caller sets its detector and classifier, e.g. the shipped legs_2d.yaml), whose persons go
  /// through the follow pipeline's tracking, target choice and controller. Its odometry is the
  /// wheels with a gyro (DeadReckoningPoseSource: the 3D LiDAR odometry needs rings, and 2D
  /// scan matching finds too little on an open lawn).
  people::LegPipeline2DConfig legs_2d;
};

/// One row of follow_log.csv.
struct LogRow {
  double t_s = 0;
  double mower_x = 0, mower_y = 0, mower_yaw = 0;  ///< true pose at the end of the sweep
  /// The pose the pipeline used (odometry at the sweep start + the commanded wheel speeds).
  double mower_est_x = 0, mower_est_y = 0, mower_est_yaw = 0;
  double est_x = NAN, est_y = NAN;  ///< target estimate (NaN when none)
  double true_x = 0, true_y = 0;    ///< the operator's true position
  double distance_m = NAN;          ///< L used by the safety rule (estimated), NaN when lost
  double true_distance_m = 0;
  double wheel_left = 0, wheel_right = 0;  ///< commanded wheel speeds (m/s)
  follow::FollowState state = follow::FollowState::kIdle;
  std::int64_t target_id = -1;
  std::uint32_t target_points = 0;  ///< returns on the operator in this sweep (truth)
  std::size_t people_detected = 0;
  double perception_ms = 0;
  double odometry_ms = 0;
  bool odometry_registered = true;
};

struct ClosedLoopResult {
  PoseSource pose_source = PoseSource::kOdometry;
  Pose T_world_frame = Pose::Identity();  ///< the recording frame in the world
  std::vector<LogRow> rows;
  follow::BoundaryPolygon boundary;
  std::vector<Eigen::Vector2d> operator_loop;  ///< truth: the operator's closed path
  std::vector<Eigen::Vector2d> mower_path;     ///< truth
  std::vector<Eigen::Vector2d> trail;          ///< the operator's estimated breadcrumbs
  bool stopped_by_command = false;
  double duration_s = 0;
  follow::PolygonDistance boundary_error;   ///< recorded polygon vs operator_loop
  std::size_t frames_moving_too_close = 0;  ///< wheels turning while the true L < L_s
  std::size_t frames_following = 0;
  /// Frames from the first target choice on, and those of them with the target tracked.
  std::size_t frames_target_chosen = 0, frames_target_held = 0;
  std::size_t target_switches = 0;    ///< changes of the target id after the first choice
  std::size_t frames_target_off = 0;  ///< following while the estimate is > 0.5 m off the operator
  std::optional<std::uint32_t> first_target_id;
  // Occlusions of the operator lasting >= 2 frames:
  std::size_t occlusions = 0;
  int max_stop_delay_frames = -1;    ///< frames from the first hidden sweep to wheels at 0
  int max_resume_delay_frames = -1;  ///< frames from visible again to moving again (-1 never)
  bool resumed_after_every_occlusion = true;
  double mean_perception_ms = 0;
  // The pose source against the truth, lidar poses at every sweep start (recording frame).
  std::vector<Pose> lidar_poses_used, lidar_poses_true;
  std::optional<TrajectoryMetrics> odometry_accuracy;  ///< with the odometry as the pose source
  std::size_t odometry_unregistered = 0;               ///< sweeps kept at the motion prior
  std::size_t odometry_degenerate = 0;
  double mean_odometry_ms = 0;
};

/// Runs the closed loop on `scene` (a lawn scene) until the stop command or the time limit.
ClosedLoopResult run_closed_loop(const sim::Scene& scene, const SensorModel& sensor,
                                 const ClosedLoopConfig& config);

/// CSV text of the log with the header
/// t,mower_x,mower_y,mower_yaw,est_x,est_y,true_target_x,true_target_y,distance,true_distance,
/// wheel_left,wheel_right,state,target_id,target_points,people_detected,mower_est_x,mower_est_y,
/// mower_est_yaw
std::string log_csv(const std::vector<LogRow>& rows);

}  // namespace fieldlidar::loops
