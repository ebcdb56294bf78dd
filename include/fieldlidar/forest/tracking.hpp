#pragma once
/// \file Pose tracking from trunks (seed 003, last step, and past it): trunk landmarks associated
/// across scans by the geometric consistency of landmark pairs, 6-DoF motion from the trunk axes
/// (x, y, yaw) and the ground plane (roll, pitch, height), and a trunk map kept over a drive.

#include <cstdint>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "fieldlidar/core/point_cloud.hpp"
#include "fieldlidar/core/pose.hpp"
#include "fieldlidar/forest/trunks.hpp"

namespace fieldlidar::forest {

/// A trunk as a landmark: its axis through the stem at breast height.
struct TrunkLandmark {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  ///< axis at DBH height
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  double dbh_m = 0.0;
};

/// Landmarks of the trees of one scan, in its frame.
std::vector<TrunkLandmark> landmarks_of(std::span<const Tree> trees, double dbh_height_m = 1.3);

struct AssociationConfig {
  double gate_m = 1.0;             ///< a candidate pair lies this close under the prior pose
  double dbh_tolerance_m = 0.06;   ///< and differs this little in DBH (plus 30 % of it)
  double pair_tolerance_m = 0.15;  ///< two pairs agree when their distances differ this little
  std::size_t min_matches = 2;
};

/// Matches (index in `reference`, index in `current`): the largest set of candidate pairs whose
/// mutual horizontal distances agree (greedy clique in the consistency graph). `prior` maps the
/// current frame into the reference one. No identity from anywhere else is used.
std::vector<std::pair<std::size_t, std::size_t>> associate_trunks(
    std::span<const TrunkLandmark> reference, std::span<const TrunkLandmark> current,
    const Pose& prior, const AssociationConfig& config = {});

/// A plane n . x + d = 0 with n unit and pointing up.
struct GroundPlane {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double offset = 0.0;
  bool ok = false;
};

/// Least-squares plane of the ground points between min_r and max_r (horizontal) of the sensor
/// at the origin, refitted once without the points farther than 2.5 RMS; ok = false with fewer
/// than 30 points.
GroundPlane fit_ground_plane(const PointCloud& cloud, std::span<const std::uint8_t> is_ground,
                             double min_r_m = 2.0, double max_r_m = 10.0);

struct MotionConfig {
  double trunk_sigma_m = 0.05;     ///< of an axis position across it
  double plane_sigma_m = 0.01;     ///< of the ground plane's height under the sensor
  double plane_sigma_rad = 0.005;  ///< of its normal
  double axis_sigma_rad = 0.03;    ///< of a stem's axis direction in one scan
  int iterations = 8;
};

/// Pose of the current scan in the reference frame: Gauss-Newton on the distances of matched
/// current axis points to the reference axes, and on the current ground plane against the
/// reference one (when both are ok), from `initial`.
Pose estimate_trunk_motion(std::span<const TrunkLandmark> reference,
                           std::span<const TrunkLandmark> current,
                           std::span<const std::pair<std::size_t, std::size_t>> matches,
                           const GroundPlane& reference_ground, const GroundPlane& current_ground,
                           const Pose& initial, const MotionConfig& config = {});

/// One tree of the map, merged over its observations.
struct MappedTrunk {
  std::uint32_t id = 0;
  TrunkLandmark landmark;  ///< world frame
  double weight = 0.0;     ///< sum of the observation weights
  double dbh_weighted_sum = 0.0;
  double dbh_weight = 0.0;  ///< an observation with dbh_uncertain weighs 1/1000 of its weight
  Eigen::Vector3d point_weighted_sum = Eigen::Vector3d::Zero();
  double base_z_m = 0.0;
  double height_seen_m = 0.0;
  double arc_deg = 0.0;
  double residual_m = 0.0;
  std::size_t observations = 0;
  std::size_t thicker_seen = 0;  ///< scans with an unmatched thicker stem around it (a branch?)
};

struct TrackerConfig {
  TreeConfig trees;
  AssociationConfig association;
  MotionConfig motion;
  double sweep_period_s = 0.1;  ///< for de-skewing by the predicted motion (needs point times)
  bool deskew = true;
  double motion_smoothing = 0.3;         ///< weight of the newest motion in the predicted one
  double map_radius_m = 25.0;            ///< map trunks this near the predicted pose are matched
  double new_trunk_distance_m = 0.5;     ///< an unmatched tree this near a mapped one is not added
  double max_range_m = 15.0;             ///< trees farther than this do not enter the map
  std::size_t map_min_observations = 5;  ///< a map trunk is reported once seen in this many scans
};

struct TrackResult {
  Pose T_world_lidar = Pose::Identity();
  std::size_t trees = 0;    ///< extracted in the scan
  std::size_t matched = 0;  ///< associated with the map
  bool tracked = false;     ///< false: too few matches, the prior was kept
};

/// Tracks the pose of each scan against a trunk map built over the drive; the first scan is the
/// world frame. A prior motion (e.g. from odometry) replaces the constant-velocity prediction.
class TrunkTracker {
 public:
  explicit TrunkTracker(const TrackerConfig& config = {});
  TrackResult track(const PointCloud& cloud, std::span<const std::uint8_t> is_ground,
                    const std::optional<Pose>& prior_motion = std::nullopt);
  const std::vector<MappedTrunk>& map() const { return map_; }
  /// Map trunks seen in at least config.map_min_observations scans, as trees (world frame).
  std::vector<Tree> map_trees() const;
  const Pose& pose() const { return T_world_lidar_; }

 private:
  void update_map(std::span<const Tree> trees, std::span<const TrunkLandmark> current,
                  std::span<const std::pair<std::size_t, std::size_t>> matches,
                  std::span<const std::size_t> map_index);
  TrackerConfig config_;
  std::vector<MappedTrunk> map_;
  Pose T_world_lidar_ = Pose::Identity();
  Pose last_motion_ = Pose::Identity();
  Pose smooth_motion_ = Pose::Identity();
  GroundPlane world_ground_;  ///< previous scan's ground plane, world frame
  bool started_ = false;
};

}  // namespace fieldlidar::forest
