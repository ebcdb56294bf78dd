#include "fieldlidar/follow/replay.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "fieldlidar/people/leg_detector.hpp"
#include "fieldlidar/segmentation/range_image.hpp"

namespace fieldlidar::follow {

Perception perceive_2d(people::LegPipeline2D& legs, double stamp_s, const PointCloud& scan,
                       const Pose& T_fixed_sensor, bool pose_known) {
  const Eigen::Isometry2d T_2d = isometry_2d(planar(T_fixed_sensor));
  // A laser mounted upside down: its scan mirrored back (its heading is its x axis either way).
  const auto points = people::scan_points_2d(scan, people::upside_down(T_fixed_sensor));
  const auto det = pose_known ? legs.process(stamp_s, points, T_2d) : legs.process(stamp_s, points);
  Perception perception;
  for (const auto& l : det.legs) perception.legs_m.push_back(T_2d * l.position_m);
  for (const auto& p : det.people)
    if (p.seen) {
      perception.people_m.push_back(T_2d * p.position_m);
      perception.people_ids.push_back(p.track);
    }
  return perception;
}

FollowState counted_state(bool target_chosen, FollowState controller) {
  return target_chosen ? controller : FollowState::kIdle;
}

bool is_planar_scan(const PointCloud& cloud) {
  if (cloud.fields.ring) return cloud.ring_count() <= 1;
  return std::all_of(cloud.points.begin(), cloud.points.end(),
                     [](const Point& p) { return p.z == 0.f; });
}

void ensure_rings(PointCloud& cloud, const SensorModel& sensor) {
  if (cloud.fields.ring) return;
  const auto rings = segmentation::estimate_rings(cloud, sensor);
  for (std::size_t i = 0; i < cloud.size(); ++i) cloud.points[i].ring = rings.rings[i];
  cloud.fields.ring = true;
}

double ReplaySummary::target_held_fraction() const {
  return frames_with_target_chosen ? double(frames_target_held) / double(frames_with_target_chosen)
                                   : 0.0;
}

double ReplaySummary::target_held_fraction_between_gaps() const {
  const std::size_t chosen = frames_with_target_chosen - frames_lost_after_gaps;
  return chosen ? double(frames_target_held) / double(chosen) : 0.0;
}

FollowReplay::FollowReplay(const SensorModel& sensor, const ReplayConfig& config)
    : config_(config),
      sensor_(sensor),
      pipeline_(sensor, config.follow),
      legs_2d_(config.legs_2d) {}

ReplayFrame FollowReplay::step(PointCloud cloud, double stamp_s,
                               const std::optional<Pose>& T_odom_base) {
  ReplayFrame f;
  f.stamp_s = stamp_s;
  const Pose T_base = T_odom_base ? *T_odom_base : Pose::Identity();
  const Pose T = T_base * config_.T_base_sensor;  // the sensor in the odometry frame
  f.mower = planar(T_base);
  const double dt_s = last_stamp_s_ && stamp_s > *last_stamp_s_ ? stamp_s - *last_stamp_s_
                                                                : config_.nominal_period_s;
  const auto t0 = std::chrono::steady_clock::now();
  Perception perception;
  if (is_planar_scan(cloud)) {
    // A 2D scan: the leg pipeline tracks legs and persons in the odometry frame.
    perception = perceive_2d(legs_2d_, stamp_s, cloud, T, T_odom_base.has_value());
  } else {
    ensure_rings(cloud, sensor_);
    perception = perceive(cloud, sensor_, T, config_.follow);
  }
  f.perception_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  f.people_detected = perception.people_m.size();
  f.output = pipeline_.follow(std::move(perception), f.mower, stamp_s, dt_s);

  // Counts.
  auto& s = summary_;
  ++s.frames;
  if (last_stamp_s_ && stamp_s - *last_stamp_s_ > config_.gap_s) {
    ++s.recording_gaps;
    after_gap_ = true;
  }
  if (!first_stamp_s_) first_stamp_s_ = stamp_s;
  s.duration_s = stamp_s - *first_stamp_s_;
  last_stamp_s_ = stamp_s;
  if (last_mower_) s.path_length_m += (f.mower.xy() - last_mower_->xy()).norm();
  last_mower_ = f.mower;
  const auto& id = f.output.target_id;
  if (id) {
    ++s.frames_with_target_chosen;
    if (!s.first_target_id) s.first_target_id = *id;
    if (!target_ids_.empty() && target_ids_.back() != *id) ++s.target_switches;
    if (std::find(target_ids_.begin(), target_ids_.end(), *id) == target_ids_.end())
      ++s.distinct_target_ids;
    target_ids_.push_back(*id);
    if (f.output.target_world_m) {
      ++s.frames_target_held;
      after_gap_ = false;
    } else if (after_gap_) {
      ++s.frames_lost_after_gaps;
    }
  }
  const FollowState state = counted_state(id.has_value(), f.output.control.state);
  ++s.frames_by_state[std::size_t(state)];
  if (state == FollowState::kFollowing) ++s.frames_following;
  if (last_state_ == FollowState::kFollowing && state != FollowState::kFollowing) ++s.stops;
  last_state_ = state;
  perception_ms_sum_ += f.perception_ms;
  s.mean_perception_ms = perception_ms_sum_ / double(s.frames);
  s.max_perception_ms = std::max(s.max_perception_ms, f.perception_ms);
  return f;
}

}  // namespace fieldlidar::follow
