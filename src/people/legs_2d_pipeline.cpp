#include "fieldlidar/people/legs_2d_pipeline.hpp"

#include "fieldlidar/people/scan_resample.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace fieldlidar::people {

namespace {

/// Drops map entries whose track no longer exists.
template <class Map>
void prune(Map& m, const PersonTracker& tracker) {
  for (auto it = m.begin(); it != m.end();)
    it = tracker.find(it->first) ? std::next(it) : m.erase(it);
}

}  // namespace

LegPipeline2DConfig LegPipeline2D::resolved(LegPipeline2DConfig c) {
  // The occupied-space rule's margins left unset (NaN) are the classifier's own.
  if (const auto& k = c.detector.classifier) {
    if (std::isnan(c.occupied_leg_score_min)) c.occupied_leg_score_min = k->occupied_score_min;
    if (std::isnan(c.occupied_leg_evidence_min))
      c.occupied_leg_evidence_min = k->occupied_evidence_min;
    if (c.sure_leg_radius_m > 0) c.joint.occupied_keep_score = c.occupied_leg_score_min;
  }
  return c;
}

LegPipeline2D::LegPipeline2D(LegPipeline2DConfig config)
    : config_(resolved(std::move(config))),
      odometry_(config_.scan_matcher),
      world_background_(config_.background),
      sensor_background_(config_.background),
      occupancy_(config_.occupancy),
      sensor_occupancy_(config_.occupancy),
      person_occupancy_(config_.occupancy),
      legs_(config_.leg_tracker),
      persons_(config_.person_tracker),
      persons_joint_(config_.joint) {
  if (!(config_.unjudged_occupancy_weight >= 0 && config_.unjudged_occupancy_weight <= 1))
    throw std::invalid_argument("LegPipeline2DConfig: unjudged_occupancy_weight " +
                                std::to_string(config_.unjudged_occupancy_weight) +
                                " is outside 0..1");
  config_.unjudged_occupancy_weight =
      std::min(config_.unjudged_occupancy_weight, config_.compact_occupancy_weight);
  person_grid_ = config_.unjudged_occupancy_weight != config_.compact_occupancy_weight;
}

void LegPipeline2D::add_held_legs(
    std::span<const std::pair<std::size_t, std::size_t>> segments,
    std::span<const Eigen::Vector2d> pts, std::span<const Eigen::Vector2d> world, bool moving_frame,
    std::vector<LegObservation>& obs,
    std::vector<std::pair<std::size_t, std::size_t>>& obs_range) const {
  if (!(config_.held_leg_chord_max_m > 0)) return;
  std::vector<Eigen::Vector2d> held;
  for (const auto& t : persons_joint_.tracks())
    if (t.reported) held.push_back(t.position());
  if (held.empty()) return;
  const auto& jc = config_.joint;
  const double reach = jc.gate_m + 0.5 * jc.pair_distance_max_m + config_.held_leg_margin_m;
  const std::size_t given = obs_range.size();  // segments already given to the tracker
  const StaticBackground& grid = person_grid_ ? person_occupancy_ : occupancy_;
  for (const auto& [b, e] : segments) {
    if (std::any_of(obs_range.begin(), obs_range.begin() + std::ptrdiff_t(given),
                    [&](const auto& r) { return r.first == b; }))
      continue;
    const double chord = (pts[e - 1] - pts[b]).norm();
    if (chord > config_.held_leg_chord_max_m) continue;
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (std::size_t k = b; k < e; ++k) mean += world[k];
    mean /= double(e - b);
    if (std::none_of(held.begin(), held.end(),
                     [&](const Eigen::Vector2d& h) { return (h - mean).norm() <= reach; }))
      continue;
    const auto seg_world = world.subspan(b, e - b);
    if (world_background_.is_static(seg_world) || grid.is_static(seg_world)) continue;
    if (moving_frame && sensor_occupancy_.is_static(pts.subspan(b, e - b))) continue;
    obs.push_back({mean, 0.0, chord, true});
    obs_range.emplace_back(b, e);
  }
}

bool LegPipeline2D::walking_leg(std::int64_t leg_track) const {
  if (leg_track < 0 || !(config_.walking_leg_travel_m > 0)) return false;
  const Track* t = legs_.find(std::uint32_t(leg_track));
  return t && (t->position() - t->born_m).norm() >= config_.walking_leg_travel_m &&
         t->velocity().norm() >= config_.walking_leg_speed_m_s;
}

std::vector<Eigen::Vector2d> LegPipeline2D::scan_at_classifier_step(
    std::vector<Eigen::Vector2d> pts, bool& resampled) {
  resampled = false;
  const auto& k = config_.detector.classifier;
  if (!k || !(k->scan_step_rad > 0) || !(config_.resample_min_ratio > 0)) return pts;
  if (!(laser_step_rad_ > 0)) laser_step_rad_ = scan_step_rad(pts);
  if (!(laser_step_rad_ >= config_.resample_min_ratio * k->scan_step_rad)) return pts;
  resampled = true;
  return resample_scan(pts, k->scan_step_rad, config_.detector.segment_jump_m);
}

LegPipeline2DOutput LegPipeline2D::process(double stamp_s, std::span<const Eigen::Vector2d> points,
                                           const std::optional<Eigen::Isometry2d>& pose) {
  const auto& dc = config_.detector;
  LegPipeline2DOutput out;
  // 1. Ego-motion.
  if (pose) {
    out.pose = *pose;
  } else if (config_.estimate_ego_motion) {
    out.pose = odometry_.add(points, last_pose_ ? stamp_s - last_pose_->first : 0.0);
    out.ego_motion_ok = odometry_.last_match().ok || odometry_.last_match().iterations == 0;
  }
  const bool moving_frame = pose.has_value() || config_.estimate_ego_motion;
  bool resampled = false;
  const std::vector<Eigen::Vector2d> pts =
      scan_at_classifier_step(points_in_range(points, dc), resampled);
  // A resampled scan's segments need a margin over the classifier's threshold.
  const double resample_margin = resampled ? config_.resample_score_margin : 0.0;
  out.resampled = resampled;
  std::vector<Eigen::Vector2d> world;
  world.reserve(pts.size());
  for (const auto& p : pts) world.push_back(out.pose * p);

  // 2.-3. Scored segments off the background, as leg-track candidates.
  std::vector<Eigen::Vector2d> cand, cand_world;
  std::vector<std::pair<std::size_t, std::size_t>> cand_range;
  std::vector<double> score;
  // Leg-sized segments (compact blobs: a leg, a post, a person's two legs merged) teach the
  // world occupancy grid with their own weight (compact_occupancy_weight), and the person grid
  // with unjudged_occupancy_weight when the classifier cannot judge them (too few returns and
  // not too thin for a leg, or too far). Per point: 0 not compact, 1 compact and judged, 2
  // compact and unjudged.
  std::vector<char> compact(pts.size(), 0);
  const auto segments = split_by_jump(pts, dc.segment_jump_m);
  const double judged2 = config_.judged_range_max_m * config_.judged_range_max_m;
  for (const auto& [b, e] : segments)
    if ((pts[e - 1] - pts[b]).norm() <= config_.compact_chord_max_m) {
      const double chord = (pts[e - 1] - pts[b]).norm();
      const bool judged = (e - b >= std::size_t(std::max(0, config_.judged_points_min)) ||
                           chord <= config_.judged_chord_max_m) &&
                          (0.5 * (pts[b] + pts[e - 1])).squaredNorm() <= judged2;
      std::fill(compact.begin() + std::ptrdiff_t(b), compact.begin() + std::ptrdiff_t(e),
                char(judged ? 1 : 2));
    }
  const bool trace = config_.trace_segments;
  std::vector<std::size_t> cand_trace;  // per candidate: its entry in out.segments
  // Near a reported person a sure leg still counts on the backgrounds and occupied space
  // (sure_leg_radius_m): per candidate, whether it is near one, and its background (if any).
  std::vector<Eigen::Vector2d> reported_before;  // the reported persons after the last scan
  for (const auto& t : persons_joint_.tracks())
    if (t.reported) reported_before.push_back(t.position());
  const double sure_r2 = config_.sure_leg_radius_m * config_.sure_leg_radius_m;
  auto near_reported = [&](const Eigen::Vector2d& m_world) {
    if (!(config_.sure_leg_radius_m > 0)) return false;
    return std::any_of(reported_before.begin(), reported_before.end(),
                       [&](const auto& r) { return (r - m_world).squaredNorm() <= sure_r2; });
  };
  std::vector<char> cand_near;
  std::vector<SegmentFate> cand_background;  // kPersonInput: off the backgrounds
  for (const auto& [b, e] : segments) {
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();  // sensor frame
    for (std::size_t k = b; k < e; ++k) mean += pts[k];
    mean /= double(e - b);
    SegmentTrace* tr = nullptr;
    if (trace) {
      tr = &out.segments.emplace_back();
      tr->begin = b;
      tr->end = e;
      tr->mean_m = mean;
      tr->score = std::numeric_limits<double>::quiet_NaN();
    }
    double s = 0;
    if (dc.classifier) {
      s = dc.classifier->score(segment_features(pts, b, e)) - resample_margin;
      if (tr) tr->score = s - dc.classifier->threshold;
      if (s <= config_.candidate_score_min) continue;
      s -= dc.classifier->threshold;
    } else {
      if (classify_arc(arc_features(std::span(pts).subspan(b, e - b), dc), dc) != ArcVerdict::kLeg)
        continue;
      s = 1.0;
      if (tr) tr->score = s;
    }
    if (dc.use_foreground && !in_foreground(pts, b, e, dc.foreground_margin_m)) {
      if (tr) tr->fate = SegmentFate::kNotForeground;
      continue;
    }
    const Eigen::Vector2d mean_world = out.pose * mean;
    const bool near = near_reported(mean_world);
    SegmentFate background = SegmentFate::kPersonInput;
    if (dc.use_background) {
      if (world_background_.is_static(std::span(world).subspan(b, e - b)))
        background = SegmentFate::kWorldBackground;
      else if (moving_frame && sensor_background_.is_static(std::span(pts).subspan(b, e - b)))
        background = SegmentFate::kSensorBackground;
      if (background != SegmentFate::kPersonInput && !near) {
        if (tr) tr->fate = background;
        continue;
      }
    }
    if (tr) {
      tr->fate = SegmentFate::kNotLeg;
      cand_trace.push_back(out.segments.size() - 1);
    }
    cand.push_back(mean);
    cand_world.push_back(mean_world);
    cand_range.emplace_back(b, e);
    score.push_back(s);
    cand_near.push_back(near);
    cand_background.push_back(background);
  }

  // Leg tracks carry a leg through scans where its score dips (half occluded, edge-on).
  const auto leg_update = legs_.update(stamp_s, cand_world);
  std::vector<LegObservation> obs;
  std::vector<std::size_t> obs_cand;
  std::vector<Eigen::Vector2d> per_scan_legs;  // the legs of this scan alone (no occupancy)
  for (std::size_t i = 0; i < cand.size(); ++i) {
    const auto track = leg_update.track_of_detection[i];
    double prior = 0;
    if (track >= 0) {
      double& ev = leg_evidence_[std::uint32_t(track)];
      prior = ev;
      ev = config_.evidence_decay * ev + score[i];
    }
    if (trace) out.segments[cand_trace[i]].evidence = prior;
    // Sure by the occupied-space margins (classifier units).
    const bool sure = dc.classifier && (score[i] >= config_.occupied_leg_score_min ||
                                        prior >= config_.occupied_leg_evidence_min);
    if (cand_background[i] != SegmentFate::kPersonInput && !sure) {
      if (trace) out.segments[cand_trace[i]].fate = cand_background[i];
      continue;
    }
    if (score[i] > 0 || prior > 0) {
      // A leg on occupied space is no person's leg: the occupancy grid forbids tracks there.
      const auto [b, e] = cand_range[i];
      const bool sensor_occupied =
          moving_frame && sensor_occupancy_.is_static(std::span(pts).subspan(b, e - b));
      const bool occupied =
          sensor_occupied || occupancy_.is_static(std::span(world).subspan(b, e - b));
      // Person tracks keep off the person grid (the same as the legs' unless unjudged blobs
      // count less there).
      const bool person_occupied =
          person_grid_
              ? sensor_occupied || person_occupancy_.is_static(std::span(world).subspan(b, e - b))
              : occupied;
      // Reported legs need more than the tracker's input: leg-shaped clutter passes the
      // classifier only just, and its leg tracks gather little evidence.
      // On occupied space (returns there scan after scan, from before or since the leg was
      // seen) only a leg the classifier is sure of, or whose track has gathered leg evidence,
      // is reported: there, most leg-shaped segments are furniture.
      const bool doubtful = dc.classifier && occupied &&
                            score[i] < config_.occupied_leg_score_min &&
                            prior < config_.occupied_leg_evidence_min;
      if (!dc.classifier || score[i] > config_.leg_report_margin ||
          prior > config_.leg_report_evidence) {
        per_scan_legs.push_back(cand[i]);
        if (!doubtful) out.legs.push_back({cand[i], score[i], track, prior, occupied});
      }
      const bool held_out = person_occupied && !(cand_near[i] && sure);
      if (trace)
        out.segments[cand_trace[i]].fate =
            held_out ? SegmentFate::kOccupied : SegmentFate::kPersonInput;
      if (held_out) continue;
      obs.push_back({cand_world[i], score[i] > 0 ? score[i] : config_.carried_leg_score,
                     (pts[e - 1] - pts[b]).norm()});
      obs_cand.push_back(i);
    }
  }
  prune(leg_evidence_, legs_);
  std::vector<std::pair<std::size_t, std::size_t>> obs_range;  // per observation: its segment
  for (std::size_t k : obs_cand) obs_range.push_back(cand_range[k]);
  add_held_legs(segments, pts, world, moving_frame, obs, obs_range);
  // Paired legs of this scan (seed 000, step 3 output: per scan, without the occupancy grid's
  // context), for the record.
  {
    LegDetection det;
    for (std::size_t i = 0; i < per_scan_legs.size(); ++i)
      det.legs.push_back({per_scan_legs[i], 1, std::int32_t(i)});
    pair_legs(det, dc);
    out.person_detections = det.people.size();
  }

  // 4. People: the legs off occupied space tracked jointly in the fixed frame (the occupancy
  // grid of non-person returns also forbids person tracks to stay on occupied cells).
  const auto joint = persons_joint_.update(stamp_s, obs, out.pose,
                                           person_grid_ ? &person_occupancy_ : &occupancy_);
  if (trace)
    for (std::size_t k = 0; k < obs_cand.size(); ++k)
      out.segments[cand_trace[obs_cand[k]]].person = joint.person_of_leg[k];
  std::vector<Eigen::Vector2d> reported_world;
  for (const auto id : joint.reported) {
    const JointTrack* t = persons_joint_.find(id);
    out.people.push_back({out.pose.inverse() * t->position(), t->position(), id, t->legs_now > 0});
    reported_world.push_back(t->position());
  }
  persons_.update(stamp_s, reported_world);

  // The background and the occupancy grids learn only the returns no tracked person explains
  // (a person standing still must not become occupied space).
  std::vector<char> person_point(pts.size(), 0);  // 1: a person's; 2: a walking leg's (below)
  for (std::size_t k = 0; k < obs.size(); ++k) {
    const auto id = joint.person_of_leg[k];
    if (id < 0) continue;
    const JointTrack* t = persons_joint_.find(std::uint32_t(id));
    // Reported persons, a pair standing in the follow zone while it is being confirmed, and a
    // person that walks (its planted foot stands still for a few scans in each stride).
    if (!t || !(t->reported || t->zone_pair_hits > 0 ||
                t->filter.velocity().norm() >= config_.walking_speed_m_s))
      continue;
    const auto [b, e] = obs_range[k];
    std::fill(person_point.begin() + std::ptrdiff_t(b), person_point.begin() + std::ptrdiff_t(e),
              char(1));
  }
  // Walking legs before any person track holds them: kept out of the fast grids only, the
  // slow backgrounds still learn them (furniture whose leg tracks drift as the robot turns).
  for (std::size_t i = 0; i < cand.size(); ++i)
    if (score[i] > 0 && compact[cand_range[i].first] &&
        walking_leg(leg_update.track_of_detection[i]))
      for (std::size_t k = cand_range[i].first; k < cand_range[i].second; ++k)
        person_point[k] = std::max(person_point[k], char(2));
  // The returns about a reported person that no leg updated in this scan (its legs scored
  // low, or merged with something) are not occupied space either: the person is still there.
  if (config_.held_person_radius_m > 0) {
    std::vector<Eigen::Vector2d> held;
    for (const auto& t : persons_joint_.tracks())
      if (t.reported && t.legs_now == 0) held.push_back(t.position());
    const double r2 = config_.held_person_radius_m * config_.held_person_radius_m;
    for (const auto& h : held)
      for (std::size_t k = 0; k < pts.size(); ++k)
        if ((world[k] - h).squaredNorm() <= r2) person_point[k] = 1;
  }
  // A person walking ahead of the robot keeps their place in the sensor frame: the follow zone
  // teaches the sensor-frame grid only while the sensor turns fast (furniture sweeping by).
  if (last_pose_ && stamp_s > last_pose_->first) {
    const Eigen::Rotation2Dd turn((last_pose_->second.inverse() * out.pose).linear());
    turn_rate_deg_s_ =
        std::abs(turn.smallestAngle()) / (stamp_s - last_pose_->first) * 180.0 / M_PI;
  }
  last_pose_.emplace(stamp_s, out.pose);
  const bool zone_free = turn_rate_deg_s_ < config_.zone_turn_rate_max_deg_s;
  JointTrackerConfig reach = config_.joint;  // the zone and the tracker's reach beyond it
  reach.zone_range_max_m += reach.gate_m;
  const double body2 = config_.body_range_max_m * config_.body_range_max_m;
  std::vector<Eigen::Vector2d> bg_world, bg_sensor, body_sensor, compact_world, unjudged_world,
      walking_world;
  bg_world.reserve(pts.size());
  for (std::size_t k = 0; k < pts.size(); ++k) {
    if (person_point[k] == 1) continue;
    if (pts[k].squaredNorm() <= body2) body_sensor.push_back(pts[k]);
    if (person_point[k] == 2) {
      walking_world.push_back(world[k]);
      continue;
    }
    if (!(zone_free && in_follow_zone(reach, pts[k]))) bg_sensor.push_back(pts[k]);
    (compact[k] == 0   ? bg_world
     : compact[k] == 1 ? compact_world
                       : unjudged_world)
        .push_back(world[k]);
  }
  occupancy_.update(bg_world);
  occupancy_.add(compact_world, config_.compact_occupancy_weight);
  occupancy_.add(unjudged_world, config_.compact_occupancy_weight);
  if (person_grid_) {
    person_occupancy_.update(bg_world);
    person_occupancy_.add(compact_world, config_.compact_occupancy_weight);
    person_occupancy_.add(unjudged_world, config_.unjudged_occupancy_weight);
  }
  bg_world.insert(bg_world.end(), compact_world.begin(), compact_world.end());
  bg_world.insert(bg_world.end(), unjudged_world.begin(), unjudged_world.end());
  bg_world.insert(bg_world.end(), walking_world.begin(), walking_world.end());
  world_background_.update(bg_world);
  if (moving_frame) sensor_occupancy_.update(bg_sensor);
  if (moving_frame) sensor_background_.update(body_sensor);
  return out;
}

}  // namespace fieldlidar::people
