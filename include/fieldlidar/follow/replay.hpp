#pragma once
/// \file The follow pipeline on a recording: perception, tracking, target choice, safety and the
/// controller run on recorded scans as on the mower, but the robot's motion comes from the
/// recording (its odometry, or standing still), so the wheel commands are only logged. Tells how
/// often the target is held and how often, and why, the mower would have stopped.
///
/// 2D laser scans (one ring) are perceived by people::LegPipeline2D (legs, leg tracks, persons),
/// 3D sweeps by follow::perceive(); either way the persons go through FollowPipeline::follow().
/// Positions in the recording's odometry frame (m), yaw in rad, times in s.

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "fieldlidar/core/point_cloud.hpp"
#include "fieldlidar/core/pose.hpp"
#include "fieldlidar/core/sensor_model.hpp"
#include "fieldlidar/follow/pipeline.hpp"
#include "fieldlidar/people/legs_2d_pipeline.hpp"

namespace fieldlidar::follow {

/// A 2D laser scan: a ring field with one ring, or no ring field and every point at z = 0.
bool is_planar_scan(const PointCloud& cloud);
/// Gives a cloud without a ring field (KITTI, unorganised PCD) rings estimated from the sensor's
/// beam geometry (segmentation::estimate_rings); leaves a cloud with rings as it is.
void ensure_rings(PointCloud& cloud, const SensorModel& sensor);

/// Persons of a 2D laser scan (one ring, sensor frame) through the leg pipeline, placed in the
/// world (odometry) frame by the sensor's pose `T_fixed_sensor` (its planar part; a laser whose
/// z axis points down is mounted upside down, its scan mirrored back). With `pose_known` the
/// pipeline is given that pose; without, it estimates its own ego-motion by scan matching (a
/// robot taken as still that is not, or a shaking mount, would otherwise smear static returns
/// into leg tracks) and the persons are placed from the sensor frame. Only the persons a leg
/// updated in this scan are kept: the controller stops on a target it did not see (a coasted
/// report is not driven on).
Perception perceive_2d(people::LegPipeline2D& legs, double stamp_s, const PointCloud& scan,
                       const Pose& T_fixed_sensor, bool pose_known);

/// The follow state a replay counts for a frame: before any target was chosen the controller's
/// "lost" (no target) is idle.
FollowState counted_state(bool target_chosen, FollowState controller);

struct ReplayConfig {
  FollowConfig follow;
  /// Persons in 2D scans (the caller sets the detector and its classifier).
  people::LegPipeline2DConfig legs_2d;
  double nominal_period_s = 0.1;  ///< control period of the first frame (s)
  /// Consecutive frames farther apart than this (s) are a break in the recording (an extracted
  /// bag's cut), counted in ReplaySummary::recording_gaps.
  double gap_s = 1.0;
  /// The sensor's mount on the robot's base (the frame of the recorded odometry): scans are
  /// placed in the odometry frame by T_odom_base * T_base_sensor; the mower pose is the base's.
  Pose T_base_sensor = Pose::Identity();
};

/// One frame of the replay.
struct ReplayFrame {
  double stamp_s = 0;
  Pose2 mower;  ///< the recorded pose of the base (odometry frame), or the origin
  FrameOutput output;
  /// Persons reported by the perception this frame (2D: the leg pipeline's tracked persons).
  std::size_t people_detected = 0;
  double perception_ms = 0;
};

/// Counts over a replay. "Held": the target is chosen and tracked this frame (not lost).
struct ReplaySummary {
  std::size_t frames = 0;
  double duration_s = 0;
  std::size_t frames_with_target_chosen = 0;  ///< from the first choice on
  std::size_t frames_target_held = 0;
  std::size_t frames_following = 0;  ///< wheels commanded to follow
  /// Frames by controller state (FollowState order): idle (no target chosen yet), following,
  /// too close, too far, lost.
  std::array<std::size_t, 5> frames_by_state{};
  std::size_t stops = 0;  ///< transitions from following to a stopped state
  std::optional<std::uint32_t> first_target_id;
  std::size_t target_switches = 0;  ///< changes of the target id after the first choice
  std::size_t distinct_target_ids = 0;
  double mean_perception_ms = 0;
  double max_perception_ms = 0;
  double path_length_m = 0;  ///< of the recorded motion
  /// Breaks in the recording (ReplayConfig::gap_s). A target seen before a break is lost across
  /// it, and the frames after one until the target is held again are counted apart: over a
  /// break the person may be anywhere, so those frames tell the recording, not the tracker.
  std::size_t recording_gaps = 0;
  std::size_t frames_lost_after_gaps = 0;
  /// frames_target_held / frames_with_target_chosen (0 when never chosen).
  double target_held_fraction() const;
  /// The same without the frames lost after a break (frames_lost_after_gaps).
  double target_held_fraction_between_gaps() const;
};

class FollowReplay {
 public:
  /// `sensor` serves 3D sweeps (ground segmentation, leg arcs); unused for 2D scans.
  FollowReplay(const SensorModel& sensor, const ReplayConfig& config);

  /// One recorded frame in the sensor frame at `stamp_s` (3D sweeps without rings get estimated
  /// ones); `T_odom_base` the recorded base pose (nullopt: the robot stands at the origin).
  /// Stamps must not decrease.
  ReplayFrame step(PointCloud cloud, double stamp_s, const std::optional<Pose>& T_odom_base);

  const ReplaySummary& summary() const { return summary_; }
  const FollowPipeline& pipeline() const { return pipeline_; }

 private:
  ReplayConfig config_;
  SensorModel sensor_;
  FollowPipeline pipeline_;
  people::LegPipeline2D legs_2d_;
  ReplaySummary summary_;
  std::optional<double> first_stamp_s_, last_stamp_s_;
  std::optional<Pose2> last_mower_;
  std::vector<std::uint32_t> target_ids_;
  FollowState last_state_ = FollowState::kIdle;
  bool after_gap_ = false;  ///< a break came and the target has not been held since
  double perception_ms_sum_ = 0;
};

}  // namespace fieldlidar::follow
