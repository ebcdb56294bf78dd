#pragma once
/// \file The follow pipeline (seed 000, steps 1-8) for one sweep: ground -> clusters -> legs ->
/// tracker -> safety + controller -> boundary. State (tracker, trail, drive, boundary) lives in
/// FollowPipeline; each step is a free function of people/, segmentation/ and follow/.

#include <cstdint>
#include <limits>
#include <optional>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>

#include "fieldlidar/core/point_cloud.hpp"
#include "fieldlidar/core/pose.hpp"
#include "fieldlidar/core/sensor_model.hpp"
#include "fieldlidar/follow/boundary.hpp"
#include "fieldlidar/follow/controller.hpp"
#include "fieldlidar/people/body_check.hpp"
#include "fieldlidar/people/leg_detector.hpp"
#include "fieldlidar/people/tracker.hpp"
#include "fieldlidar/segmentation/clustering.hpp"
#include "fieldlidar/segmentation/ground.hpp"

namespace fieldlidar::follow {

struct FollowConfig {
  /// The robust ground without its undercut test (RobustGroundConfig::face_back_*): at a
  /// walking person's feet the beam above hits the shin nearer than the ground behind, which is
  /// the undercut pattern of a shrub; with it on, the closed loop lost the operator after the
  /// shed detour (tests/loops/test_closed_loop.cpp, occluded scenario, never resumed).
  segmentation::GroundConfig ground = [] {
    segmentation::GroundConfig g;
    g.robust.face_back_rise_m = std::numeric_limits<double>::infinity();
    return g;
  }();
  segmentation::EuclideanClusterConfig clusters = default_clusters();
  people::LegDetectorConfig legs = default_3d_legs();
  double leg_height_min_m = 0.08;  ///< leg arcs are taken from points this high above ground
  double leg_height_max_m = 0.95;  ///< up to this (m); torso and arms are above
  /// A leg pair is a person only with a body above it (people/body_check.hpp).
  people::BodyCheckConfig body;
  people::TrackerConfig tracker;
  DriveConfig drive;
  SafetyConfig safety;
  BoundaryConfig boundary;
  /// The target: this track id when set (the operator's choice), else the confirmed person
  /// within `auto_select_range_m` ahead of the mower nearest its heading (smallest bearing).
  /// A target lost longer than the tracker's reacquire_window_s is taken again the same way, by
  /// a person walking in front of the mower (PersonTracker::may_reacquire); the mower stays
  /// stopped until then.
  std::optional<std::uint32_t> target_id;
  double auto_select_range_m = 6.0;
  /// With persons from a 2D laser (Perception::people_ids set), a target chosen automatically is
  /// provisional while neither it nor the mower has moved `provisional_move_m` since the choice
  /// (m; 0 = off): a confirmed person who walks off from within `provisional_birth_range_m` of
  /// the mower (their track born there; walking as the tracker's re-acquisition asks: 1 m from
  /// there, at 0.3 m/s or more, seen in 10 frames in a row) and is ahead of it then takes the
  /// target over. At leg height two posts read as a standing pair as well as an operator's legs
  /// do; the operator is the one who walks off from in front of the mower (the 3D path's body
  /// check tells them apart, and a stroller passing by takes nothing over there).
  double provisional_move_m = 0.5;
  double provisional_birth_range_m = 3.5;
  /// With persons from a detector that tracks them (a 2D laser), a target lost for at most
  /// `quick_retake_s` is taken again by a person the detector began tracking since the loss,
  /// within `quick_retake_radius_m` of the way from where the target was last seen to where it
  /// would be had it walked on: the detector lost its person track for a scan or two (a leg
  /// jumped) and started a new one on the same legs (s, m; 0 = off). Otherwise the
  /// re-acquisition waits for the new person to walk 1 m.
  double quick_retake_s = 1.0;
  double quick_retake_radius_m = 0.75;

  /// Leg bounds for a multi-beam sensor at mower height, set by hand from the arcs of simulated
  /// VLP-16 sweeps of walking people (range noise 3 cm: smoothing and a 3 cm path step needed).
  static people::LegDetectorConfig default_3d_legs();
  /// Legs and the gap between them in one cluster; small far clusters kept.
  static segmentation::EuclideanClusterConfig default_clusters();
};

/// Perception of one sweep, positions in the world frame (m).
struct Perception {
  std::vector<Eigen::Vector2d> legs_m;
  std::vector<Eigen::Vector2d> people_m;
  /// Per person: the detector's own track id when the detector tracks people (the 2D leg
  /// pipeline's joint tracks), else empty. The follow tracker takes a lost target back at once
  /// when the detector reports the target's own track again.
  std::vector<std::int64_t> people_ids;
  std::size_t ground_points = 0;
  std::size_t clusters = 0;
  double sensor_height_m = 0;
};

/// Steps 1-2: ground removed, points outside the leg height band skipped, the rest clustered;
/// returns each cluster's point indices (and the estimated sensor height in `sensor_height_m`).
std::vector<std::vector<std::uint32_t>> leg_band_clusters(const PointCloud& cloud_lidar,
                                                          const SensorModel& sensor,
                                                          const FollowConfig& config,
                                                          double* sensor_height_m = nullptr,
                                                          std::size_t* ground_points = nullptr);
/// The 3D leg config used for a sensor: the azimuth split set from its column spacing when 0.
people::LegDetectorConfig legs_for_sensor(const people::LegDetectorConfig& legs,
                                          const SensorModel& sensor);

/// Step 3: leg arcs on several rings of the leg band's `clusters`, legs paired into people, and
/// of those the pairs with a person's body above (config.body); lidar frame, the ground
/// `sensor_height_m` below the sensor. A cloud levelled from a tilted sensor's frame passes the
/// rotation (`level_from_lidar`): its beams cross the body's bands at other heights.
people::LegDetection detect_people_3d(
    const PointCloud& cloud_lidar, std::span<const std::vector<std::uint32_t>> clusters,
    const SensorModel& sensor, double sensor_height_m, const FollowConfig& config,
    const Eigen::Matrix3d& level_from_lidar = Eigen::Matrix3d::Identity());

/// Steps 1-3: ground, clusters, leg arcs and pairing for a sweep in the lidar frame (de-skewed to
/// `T_world_lidar`), results transformed into the world frame.
Perception perceive(const PointCloud& cloud_lidar, const SensorModel& sensor,
                    const Pose& T_world_lidar, const FollowConfig& config);

struct FrameOutput {
  Perception perception;
  std::optional<std::uint32_t> target_id;
  std::optional<Eigen::Vector2d> target_world_m;  ///< the target's filtered position
  FollowController::Output control;
};

class FollowPipeline {
 public:
  FollowPipeline(const SensorModel& sensor, const FollowConfig& config);

  /// One sweep: `cloud_lidar` de-skewed to `T_world_lidar` (the sensor pose at `stamp_s`),
  /// `mower` the planar pose the wheel command applies from; `dt_s` the control period.
  FrameOutput step(const PointCloud& cloud_lidar, const Pose& T_world_lidar, const Pose2& mower,
                   double stamp_s, double dt_s);

  /// Steps 4-8 on a perception made elsewhere (e.g. 2D laser scans through
  /// people::LegPipeline2D), people in the world frame: tracking, target choice, safety and
  /// drive, boundary. step() is perceive() followed by this.
  FrameOutput follow(Perception perception, const Pose2& mower, double stamp_s, double dt_s);

  /// The stop command: closes the recorded boundary.
  BoundaryPolygon stop() const { return recorder_.close(); }

  const people::PersonTracker& tracker() const { return tracker_; }
  people::PersonTracker& tracker() { return tracker_; }
  const Trail& trail() const { return trail_; }
  const BoundaryRecorder& recorder() const { return recorder_; }
  const FollowConfig& config() const { return config_; }

 private:
  SensorModel sensor_;
  FollowConfig config_;
  people::PersonTracker tracker_;
  /// The detector's id of the person the target was last updated by (Perception::people_ids).
  std::optional<std::int64_t> target_source_;
  /// When each detector person id was first reported (s).
  std::unordered_map<std::int64_t, double> source_first_seen_s_;
  /// The lost target taken again by a detector person begun since the loss near where it would
  /// be (FollowConfig::quick_retake_s); true when it was.
  bool quick_retake(const Perception& perception, const people::TrackerUpdate& update,
                    double stamp_s);
  /// The automatic choice is provisional (FollowConfig::provisional_move_m): where the target
  /// and the mower were when it was made.
  bool provisional_ = false;
  Eigen::Vector2d chosen_at_m_ = Eigen::Vector2d::Zero(),
                  mower_at_choice_m_ = Eigen::Vector2d::Zero();
  FollowController controller_;
  Trail trail_;
  BoundaryRecorder recorder_;
};

}  // namespace fieldlidar::follow
