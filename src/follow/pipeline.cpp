#include "fieldlidar/follow/pipeline.hpp"

#include <cmath>
#include <optional>
#include <utility>

#include "fieldlidar/core/rotate_points.hpp"
#include "fieldlidar/core/segment_distance.hpp"

namespace fieldlidar::follow {

people::LegDetectorConfig FollowConfig::default_3d_legs() {
  people::LegDetectorConfig c;
  c.min_rings = 2;
  c.curve_max = 2.2;
  c.path_min_m = 0.04;
  c.path_max_m = 0.40;
  c.pair_distance_max_m = 0.70;
  c.range_min_m = 0.5;
  c.range_max_m = 12.0;
  c.segment_jump_m = 0.12;
  c.path_step_m = 0.03;
  c.smooth_window = 5;
  c.split_azimuth_gap_rad = 0.0;  // set from the sensor's column spacing in perceive()
  c.use_chord_max = true;
  c.chord_max_m = 0.22;
  return c;
}

segmentation::EuclideanClusterConfig FollowConfig::default_clusters() {
  segmentation::EuclideanClusterConfig c;
  c.tolerance_m = 0.35;
  c.min_points = 5;
  return c;
}

std::vector<std::vector<std::uint32_t>> leg_band_clusters(const PointCloud& cloud,
                                                          const SensorModel& sensor,
                                                          const FollowConfig& config,
                                                          double* sensor_height_m,
                                                          std::size_t* ground_points) {
  // Steps 1-2: ground removed, the rest clustered.
  const auto ground = segmentation::segment_ground(cloud, sensor, config.ground);
  double h = ground.sensor_height_m;
  if (!(h > 0.05)) h = sensor.mounting_height_m;
  if (sensor_height_m) *sensor_height_m = h;
  if (ground_points) *ground_points = ground.ground_count;
  // Only points in the leg height band take part (the torso is not a leg).
  std::vector<std::uint8_t> skip(ground.is_ground);
  skip.resize(cloud.size(), 0);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const double above = double(cloud.points[i].z) + h;
    if (above < config.leg_height_min_m || above > config.leg_height_max_m) skip[i] = 1;
  }
  const auto clusters = segmentation::cluster_euclidean(cloud, skip, config.clusters);
  std::vector<std::vector<std::uint32_t>> indices;
  indices.reserve(clusters.clusters.size());
  for (const auto& c : clusters.clusters) indices.push_back(c.indices);
  return indices;
}

people::LegDetectorConfig legs_for_sensor(const people::LegDetectorConfig& legs_in,
                                          const SensorModel& sensor) {
  people::LegDetectorConfig legs = legs_in;
  if (legs.split_azimuth_gap_rad <= 0)
    legs.split_azimuth_gap_rad = 2.5 * sensor.horizontal_resolution_rad();
  return legs;
}

namespace {

/// Of the confirmed persons seen this frame within `range_m` ahead of the mower that pass
/// `accept`, the one nearest the mower's heading (smallest bearing).
template <class Accept>
std::optional<std::uint32_t> person_ahead(const people::PersonTracker& tracker, const Pose2& mower,
                                          double range_m, Accept accept) {
  const Eigen::Vector2d heading(std::cos(mower.yaw_rad), std::sin(mower.yaw_rad));
  const people::Track* best = nullptr;
  double best_bearing = 0;
  for (const auto& t : tracker.tracks()) {
    const Eigen::Vector2d d = t.position() - mower.xy();
    if (!t.confirmed || t.missed_frames > 0 || d.norm() > range_m || d.dot(heading) <= 0 ||
        !accept(t))
      continue;
    const double bearing =
        std::atan2(std::abs(heading.x() * d.y() - heading.y() * d.x()), d.dot(heading));
    if (!best || bearing < best_bearing) {
      best = &t;
      best_bearing = bearing;
    }
  }
  if (!best) return std::nullopt;
  return best->id;
}

}  // namespace

people::LegDetection detect_people_3d(const PointCloud& cloud,
                                      std::span<const std::vector<std::uint32_t>> clusters,
                                      const SensorModel& sensor, double sensor_height_m,
                                      const FollowConfig& config,
                                      const Eigen::Matrix3d& level_from_lidar) {
  auto det = people::detect_legs_3d(cloud, clusters, legs_for_sensor(config.legs, sensor));
  const auto body = people::person_bodies(cloud, sensor, sensor_height_m, det.people, config.body,
                                          level_from_lidar);
  std::size_t kept = 0;
  for (std::size_t k = 0; k < det.people.size(); ++k)
    if (body[k]) det.people[kept++] = det.people[k];
  det.people.resize(kept);
  return det;
}

Perception perceive(const PointCloud& cloud_lidar, const SensorModel& sensor,
                    const Pose& T_world_lidar, const FollowConfig& config) {
  Perception out;
  // The sweep levelled by the pose's roll and pitch (heading kept): the leg band and the body
  // check measure heights from a level plane through the ground under the mower, not from the
  // sensor's own x-y plane, which a mower pitched 5 deg on rough ground tilts by 0.6 m at 7 m.
  const Pose T_world_level =
      make_pose(T_world_lidar.translation().x(), T_world_lidar.translation().y(),
                T_world_lidar.translation().z(), 0, 0, yaw_of(T_world_lidar));
  const Pose T_level_lidar = T_world_level.inverse() * T_world_lidar;
  std::optional<PointCloud> levelled;  // a copy only when the sensor is tilted
  if (!T_level_lidar.linear().isIdentity(1e-9)) {
    levelled = cloud_lidar;
    rotate_points(*levelled, T_level_lidar.linear().cast<float>());
  }
  const PointCloud& cloud = levelled ? *levelled : cloud_lidar;
  const auto indices =
      leg_band_clusters(cloud, sensor, config, &out.sensor_height_m, &out.ground_points);
  out.clusters = indices.size();
  // Step 3: leg arcs on several rings, legs paired into people with a body above.
  const auto det =
      detect_people_3d(cloud, indices, sensor, out.sensor_height_m, config, T_level_lidar.linear());
  auto to_world = [&](const Eigen::Vector2d& p) {
    return (T_world_level * Eigen::Vector3d(p.x(), p.y(), 0.0)).head<2>().eval();
  };
  for (const auto& l : det.legs) out.legs_m.push_back(to_world(l.position_m));
  for (const auto& p : det.people) out.people_m.push_back(to_world(p.position_m));
  return out;
}

FollowPipeline::FollowPipeline(const SensorModel& sensor, const FollowConfig& config)
    : sensor_(sensor),
      config_(config),
      tracker_(config.tracker),
      controller_(config.drive, config.safety),
      trail_(config.drive.trail_spacing_m),
      recorder_(config.boundary) {}

FrameOutput FollowPipeline::step(const PointCloud& cloud, const Pose& T_world_lidar,
                                 const Pose2& mower, double stamp_s, double dt_s) {
  return follow(perceive(cloud, sensor_, T_world_lidar, config_), mower, stamp_s, dt_s);
}

FrameOutput FollowPipeline::follow(Perception perception, const Pose2& mower, double stamp_s,
                                   double dt_s) {
  FrameOutput out;
  out.perception = std::move(perception);
  // Step 5: Kalman tracking in the world frame.
  const auto upd = tracker_.update(stamp_s, out.perception.people_m);
  // Step 4: the target, by id when the operator chose one, else the person ahead.
  if (!tracker_.target_id()) {
    if (config_.target_id) {
      tracker_.select_target(*config_.target_id);
    } else {
      // The operator stands in front of the mower to start: of the confirmed persons ahead, the
      // one nearest the mower's heading (smallest bearing), not the nearest one (leg-like posts
      // or a bystander beside the mower may be nearer).
      if (const auto id = person_ahead(tracker_, mower, config_.auto_select_range_m,
                                       [](const people::Track&) { return true; });
          id && tracker_.select_target(*id)) {
        provisional_ = config_.provisional_move_m > 0 && !out.perception.people_ids.empty();
        chosen_at_m_ = tracker_.target()->position();
        mower_at_choice_m_ = mower.xy();
      }
    }
  } else if (provisional_) {
    // Nobody has moved since the automatic choice: a person walking off ahead is the operator.
    const people::Track* t = tracker_.target();
    if (!t || (t->position() - chosen_at_m_).norm() >= config_.provisional_move_m ||
        (mower.xy() - mower_at_choice_m_).norm() >= config_.provisional_move_m) {
      provisional_ = false;
    } else if (const auto id = person_ahead(
                   tracker_, mower, config_.auto_select_range_m, [&](const people::Track& c) {
                     return c.id != t->id &&
                            (c.born_m - mower.xy()).norm() <= config_.provisional_birth_range_m &&
                            people::walks(c, tracker_.config());
                   })) {
      provisional_ = !tracker_.select_target(*id);
      if (!provisional_) target_source_.reset();
    }
  }
  // A detector that tracks people itself (2D legs) vouches for identity: the lost target's own
  // person reported again is the target again, wherever and however it moves.
  bool retaken = false;
  const auto& ids = out.perception.people_ids;
  if (ids.size() == upd.track_of_detection.size() && tracker_.target_id()) {
    for (std::size_t j = 0; j < ids.size(); ++j)
      if (upd.track_of_detection[j] == std::int64_t(*tracker_.target_id())) target_source_ = ids[j];
    if (tracker_.target_lost() && target_source_)
      for (std::size_t j = 0; j < ids.size() && !retaken; ++j)
        if (ids[j] == *target_source_ && upd.track_of_detection[j] >= 0)
          retaken = tracker_.retake(std::uint32_t(upd.track_of_detection[j]));
    if (!retaken) retaken = quick_retake(out.perception, upd, stamp_s);
    for (const auto id : ids) source_first_seen_s_.try_emplace(id, stamp_s);
  }
  // After the tracker's re-acquisition window the lost operator takes the mower on again as at
  // the start: by walking in front of it (the mower stays stopped until then).
  if (tracker_.target_lost() && tracker_.target_lost_s() > tracker_.config().reacquire_window_s)
    if (const auto id =
            person_ahead(tracker_, mower, config_.auto_select_range_m,
                         [&](const people::Track& t) { return tracker_.may_reacquire(t); }))
      tracker_.reacquire(*id);
  out.target_id = tracker_.target_id();
  std::optional<Eigen::Vector2d> target_mower;
  if (const auto* t = tracker_.target()) {
    out.target_world_m = t->position();
    if (upd.target_updated || retaken) trail_.add(t->position());
    // The target in the mower frame (seed 000: P(xc, yc)).
    const Eigen::Vector2d d = t->position() - mower.xy();
    const double c = std::cos(mower.yaw_rad), s = std::sin(mower.yaw_rad);
    target_mower = Eigen::Vector2d(c * d.x() + s * d.y(), -s * d.x() + c * d.y());
  }
  // Steps 6-7: safety rule, then the drive.
  out.control = controller_.step(mower, target_mower, trail_, dt_s);
  // Step 8: the boundary is where the mower drives while following.
  recorder_.record(mower.xy(), out.control.state == FollowState::kFollowing);
  return out;
}

bool FollowPipeline::quick_retake(const Perception& perception, const people::TrackerUpdate& update,
                                  double stamp_s) {
  const double lost_s = tracker_.target_lost_s();
  if (!tracker_.target_lost() || config_.quick_retake_s <= 0 || lost_s > config_.quick_retake_s)
    return false;
  // Between where the target was last seen and where it would be had it walked on (it may
  // have stopped, or its last velocity may be a broken track's).
  const Eigen::Vector2d last = tracker_.target_last_m(), walked_on = tracker_.target_predicted_m();
  std::optional<std::size_t> best;
  double best_d = config_.quick_retake_radius_m;
  for (std::size_t j = 0; j < perception.people_ids.size(); ++j) {
    const auto seen = source_first_seen_s_.find(perception.people_ids[j]);
    if (update.track_of_detection[j] < 0 ||
        (seen != source_first_seen_s_.end() && seen->second < stamp_s - lost_s))
      continue;  // not followed by the tracker, or a person the detector had before the loss
    const double d = point_segment_distance(perception.people_m[j], last, walked_on);
    if (d <= best_d) best = j, best_d = d;
  }
  if (!best || !tracker_.retake(std::uint32_t(update.track_of_detection[*best]))) return false;
  target_source_ = perception.people_ids[*best];
  return true;
}

}  // namespace fieldlidar::follow
