#include "fieldlidar/people/legs_2d_pipeline.hpp"

#include <algorithm>

namespace fieldlidar::people {

namespace {

/// Drops map entries whose track no longer exists.
template <class Map>
void prune(Map& m, const PersonTracker& tracker) {
  for (auto it = m.begin(); it != m.end();)
    it = tracker.find(it->first) ? std::next(it) : m.erase(it);
}

}  // namespace

LegPipeline2D::LegPipeline2D(LegPipeline2DConfig config)
    : config_(std::move(config)),
      odometry_(config_.scan_matcher),
      world_background_(config_.background),
      sensor_background_(config_.background),
      legs_(config_.leg_tracker),
      persons_(config_.person_tracker) {}

LegPipeline2DOutput LegPipeline2D::process(double stamp_s, std::span<const Eigen::Vector2d> points,
                                           const std::optional<Eigen::Isometry2d>& pose) {
  const auto& dc = config_.detector;
  LegPipeline2DOutput out;
  // 1. Ego-motion.
  if (pose) {
    out.pose = *pose;
  } else if (config_.estimate_ego_motion) {
    out.pose = odometry_.add(points);
    out.ego_motion_ok = odometry_.last_match().ok || odometry_.last_match().iterations == 0;
  }
  const bool moving_frame = pose.has_value() || config_.estimate_ego_motion;
  const std::vector<Eigen::Vector2d> pts = points_in_range(points, dc);
  std::vector<Eigen::Vector2d> world;
  world.reserve(pts.size());
  for (const auto& p : pts) world.push_back(out.pose * p);

  // 2.-3. Scored segments off the background, as leg-track candidates.
  std::vector<Eigen::Vector2d> cand, cand_world;
  std::vector<double> score;
  for (const auto& [b, e] : split_by_jump(pts, dc.segment_jump_m)) {
    double s = 0;
    if (dc.classifier) {
      s = dc.classifier->score(segment_features(pts, b, e));
      if (s <= config_.candidate_score_min) continue;
      s -= dc.classifier->threshold;
    } else {
      if (classify_arc(arc_features(std::span(pts).subspan(b, e - b), dc), dc) != ArcVerdict::kLeg)
        continue;
      s = 1.0;
    }
    if (dc.use_foreground && !in_foreground(pts, b, e, dc.foreground_margin_m)) continue;
    if (dc.use_background) {
      if (world_background_.is_static(std::span(world).subspan(b, e - b))) continue;
      if (moving_frame && sensor_background_.is_static(std::span(pts).subspan(b, e - b))) continue;
    }
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (std::size_t k = b; k < e; ++k) mean += pts[k];
    mean /= double(e - b);
    cand.push_back(mean);
    cand_world.push_back(out.pose * mean);
    score.push_back(s);
  }
  world_background_.update(world);
  if (moving_frame) sensor_background_.update(pts);

  const auto leg_update = legs_.update(stamp_s, cand_world);
  LegDetection det;
  for (std::size_t i = 0; i < cand.size(); ++i) {
    const auto track = leg_update.track_of_detection[i];
    double prior = 0;
    if (track >= 0) {
      double& e = leg_evidence_[std::uint32_t(track)];
      prior = e;
      e = config_.evidence_decay * e + score[i];
    }
    if (score[i] > 0 || prior > 0) {
      out.legs.push_back({cand[i], score[i], track});
      det.legs.push_back({cand[i], 1, std::int32_t(i)});
    }
  }
  prune(leg_evidence_, legs_);

  // 4. People: paired legs, tracked in the fixed frame, reported once they have walked.
  pair_legs(det, dc);
  // A pair whose legs are both legs only by their tracks' past evidence is no new evidence of a
  // person: at least one leg must pass the classifier in this scan.
  std::erase_if(det.people, [&](const Person& p) {
    return out.legs[p.legs[0]].score <= 0 && out.legs[p.legs[1]].score <= 0;
  });
  out.person_detections = det.people.size();
  std::vector<Eigen::Vector2d> people_world;
  for (const auto& p : det.people) people_world.push_back(out.pose * p.position_m);
  // A person who has walked keeps being tracked through scans where only one leg is seen (the
  // other occluded or merged with it): the nearest unpaired leg near the prediction stands in.
  if (config_.single_leg_radius_m > 0) {
    std::vector<char> paired(det.legs.size(), 0);
    for (const auto& p : det.people) paired[p.legs[0]] = paired[p.legs[1]] = 1;
    for (const auto& t : persons_.tracks()) {
      const auto w = person_walk_.find(t.id);
      if (!t.confirmed || t.missed_frames > 1 || w == person_walk_.end() || !w->second.walked)
        continue;
      const Eigen::Vector2d predicted = t.position() + t.velocity() * (stamp_s - t.stamp_s);
      bool has_pair = false;
      for (const auto& q : people_world)
        has_pair = has_pair || (q - predicted).norm() < config_.single_leg_radius_m;
      if (has_pair) continue;
      int best = -1;
      double best_d = config_.single_leg_radius_m;
      for (std::size_t i = 0; i < det.legs.size(); ++i) {
        if (paired[i]) continue;
        const double d = (out.pose * det.legs[i].position_m - predicted).norm();
        if (d < best_d) {
          best_d = d;
          best = int(i);
        }
      }
      if (best < 0) continue;
      paired[std::size_t(best)] = 1;
      det.people.push_back(
          {det.legs[std::size_t(best)].position_m, {std::size_t(best), std::size_t(best)}});
      people_world.push_back(out.pose * det.legs[std::size_t(best)].position_m);
    }
  }
  const auto person_update = persons_.update(stamp_s, people_world);
  for (std::size_t i = 0; i < det.people.size(); ++i) {
    const auto id = person_update.track_of_detection[i];
    if (id < 0) continue;
    const auto key = std::uint32_t(id);
    Walk& walk = person_walk_.try_emplace(key, Walk{people_world[i]}).first->second;
    walk.walked =
        walk.walked || (people_world[i] - walk.first_m).norm() >= config_.person_min_travel_m;
    const Track* t = persons_.find(key);
    if (t && t->confirmed && walk.walked)
      out.people.push_back({det.people[i].position_m, people_world[i], key});
  }
  prune(person_walk_, persons_);
  return out;
}

}  // namespace fieldlidar::people
