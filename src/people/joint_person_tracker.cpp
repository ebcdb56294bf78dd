#include "fieldlidar/people/joint_person_tracker.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace fieldlidar::people {

namespace {

/// One way to update a track: a pair of legs (b >= 0) or one leg (b = -1).
struct Hypothesis {
  double cost = 0;
  std::size_t track = 0;
  int a = -1, b = -1;
};

Track new_filter(std::uint32_t id, const Eigen::Vector2d& p, double stamp_s, double sigma_m) {
  Track t;
  t.id = id;
  t.state << p.x(), 0, p.y(), 0;
  t.covariance = Eigen::Vector4d(sigma_m * sigma_m, 1.0, sigma_m * sigma_m, 1.0).asDiagonal();
  t.hits = 1;
  t.last_update_s = t.stamp_s = t.born_s = stamp_s;
  return t;
}

bool on_occupied(const StaticBackground* grid, const Eigen::Vector2d& p) {
  return grid && grid->is_static(std::span<const Eigen::Vector2d>(&p, 1));
}

}  // namespace

bool in_follow_zone(const JointTrackerConfig& c, const Eigen::Vector2d& sensor_point) {
  const double r = sensor_point.norm();
  return r >= c.zone_range_min_m && r <= c.zone_range_max_m &&
         sensor_point.x() >= r * std::cos(c.zone_half_angle_deg * M_PI / 180.0);
}

JointPersonTracker::JointPersonTracker(const JointTrackerConfig& config) : config_(config) {}

const JointTrack* JointPersonTracker::find(std::uint32_t id) const {
  for (const auto& t : tracks_)
    if (t.id == id) return &t;
  return nullptr;
}

JointUpdate JointPersonTracker::update(double stamp_s, std::span<const LegObservation> legs,
                                       const Eigen::Isometry2d& sensor_pose,
                                       const StaticBackground* occupied) {
  if (started_ && stamp_s < stamp_s_)
    throw std::invalid_argument("JointPersonTracker: scan time " + std::to_string(stamp_s) +
                                " s is before the previous " + std::to_string(stamp_s_) + " s");
  const auto& c = config_;
  const double dt = started_ ? stamp_s - stamp_s_ : 0.0;
  started_ = true;
  stamp_s_ = stamp_s;
  for (auto& t : tracks_) {
    kalman_predict(t.filter, dt, c.accel_sigma_m_s2);
    t.legs_now = 0;
    t.sure_leg_now = false;
  }
  const double pair2 = c.pair_distance_max_m * c.pair_distance_max_m;
  auto standing_shape = [&](const LegObservation& a, const LegObservation& b) {
    return a.width_m <= c.standing_leg_width_max_m && b.width_m <= c.standing_leg_width_max_m &&
           (a.position_m - b.position_m).norm() <= c.standing_pair_distance_max_m;
  };
  auto capped = [&](double s) { return std::min(s - c.score_offset, c.score_cap); };
  auto gain_of = [&](const LegObservation& l) { return l.carry_only ? 0.0 : capped(l.score); };

  // Hypotheses of each track: every pair and every single leg within the gate.
  std::vector<Hypothesis> hyp;
  for (std::size_t k = 0; k < tracks_.size(); ++k) {
    const Eigen::Vector2d pred = tracks_[k].position();
    const bool reported = tracks_[k].reported;
    for (std::size_t i = 0; i < legs.size(); ++i) {
      if (legs[i].carry_only && !reported) continue;
      const double di = (legs[i].position_m - pred).norm();
      if (di > c.gate_m + 0.5 * c.pair_distance_max_m) continue;
      if (di <= c.gate_m) hyp.push_back({di, k, int(i), -1});
      for (std::size_t j = i + 1; j < legs.size(); ++j) {
        if (legs[j].carry_only && !reported) continue;
        if ((legs[i].position_m - legs[j].position_m).squaredNorm() > pair2) continue;
        const bool carried = legs[i].carry_only || legs[j].carry_only;
        if (capped(legs[i].score) + capped(legs[j].score) <= 0 && !carried) continue;
        const double d = (0.5 * (legs[i].position_m + legs[j].position_m) - pred).norm();
        if (d <= c.gate_m) hyp.push_back({d - c.pair_bonus_m, k, int(i), int(j)});
      }
    }
  }
  std::sort(hyp.begin(), hyp.end(),
            [](const Hypothesis& x, const Hypothesis& y) { return x.cost < y.cost; });

  JointUpdate out;
  out.person_of_leg.assign(legs.size(), -1);
  std::vector<char> track_done(tracks_.size(), 0);
  auto used = [&](int i) { return i >= 0 && out.person_of_leg[std::size_t(i)] >= 0; };
  for (const auto& h : hyp) {
    if (track_done[h.track] || used(h.a) || used(h.b)) continue;
    track_done[h.track] = 1;
    JointTrack& t = tracks_[h.track];
    const auto& la = legs[std::size_t(h.a)];
    Eigen::Vector2d z = la.position_m;
    double gain = c.single_weight * gain_of(la);
    double sigma = c.single_sigma_m;
    out.person_of_leg[std::size_t(h.a)] = t.id;
    if (h.b >= 0) {
      const auto& lb = legs[std::size_t(h.b)];
      z = 0.5 * (la.position_m + lb.position_m);
      gain = gain_of(la) + gain_of(lb);
      sigma = c.pair_sigma_m;
      out.person_of_leg[std::size_t(h.b)] = t.id;
      ++t.pair_hits;
      if (standing_shape(la, lb)) ++t.standing_pair_hits;
    }
    if (!la.carry_only || (h.b >= 0 && !legs[std::size_t(h.b)].carry_only)) t.scored_s = stamp_s;
    kalman_update(t.filter, z, sigma);
    const Eigen::Vector2d v = t.filter.velocity();
    if (v.norm() > c.max_speed_m_s) {
      const Eigen::Vector2d vc = v * (c.max_speed_m_s / v.norm());
      t.filter.state[1] = vc.x();
      t.filter.state[3] = vc.y();
    }
    t.evidence = c.evidence_decay * t.evidence + gain;
    ++t.hits;
    t.filter.missed_frames = 0;
    t.filter.last_update_s = stamp_s;
    t.legs_now = h.b >= 0 ? 2 : 1;
    t.sure_leg_now = la.score >= c.occupied_keep_score ||
                     (h.b >= 0 && legs[std::size_t(h.b)].score >= c.occupied_keep_score);
  }
  for (std::size_t k = 0; k < tracks_.size(); ++k)
    if (!track_done[k]) {
      tracks_[k].evidence *= c.evidence_decay;
      ++tracks_[k].filter.missed_frames;
    }

  // Walked distance, follow zone, occupied space, reporting.
  const Eigen::Isometry2d to_sensor = sensor_pose.inverse();
  auto in_zone = [&](const Eigen::Vector2d& p) { return in_follow_zone(c, to_sensor * p); };
  for (auto& t : tracks_) {
    t.travel_m = std::max(t.travel_m, (t.position() - t.born_m).norm());
    if (!in_zone(t.position()))
      t.zone_pair_hits = 0;
    else if (t.legs_now == 2)
      ++t.zone_pair_hits;
    const bool kept = t.reported && t.sure_leg_now;  // a leg the classifier is sure of
    t.occupied_scans = !kept && on_occupied(occupied, t.position()) ? t.occupied_scans + 1 : 0;
    if (!t.reported && t.evidence >= c.confirm_evidence && t.hits >= c.confirm_hits &&
        (t.travel_m >= c.min_travel_m || t.zone_pair_hits >= c.zone_confirm_hits ||
         (c.standing_pair_hits > 0 && t.standing_pair_hits >= c.standing_pair_hits) ||
         t.evidence >= c.strong_evidence))
      t.reported = true;
  }
  std::erase_if(tracks_, [&](const JointTrack& t) {
    const double missing = stamp_s - t.filter.last_update_s;
    if (t.occupied_scans > c.occupied_max_scans) return true;
    if (t.reported)
      return missing > c.delete_after_miss_s || stamp_s - t.scored_s > c.carried_max_s;
    return missing > c.tentative_max_miss_s || t.evidence < c.evidence_min;
  });

  // Births: unused pairs (closest first), then strong single legs, never on occupied cells
  // nor next to a track.
  auto free_here = [&](const Eigen::Vector2d& p) {
    if (!p.allFinite() || on_occupied(occupied, p)) return false;
    return std::none_of(tracks_.begin(), tracks_.end(), [&](const JointTrack& t) {
      return (t.position() - p).norm() < c.birth_min_separation_m;
    });
  };
  auto birth = [&](const Eigen::Vector2d& p, double sigma, double evidence, bool pair,
                   bool standing) {
    JointTrack t;
    t.id = next_id_++;
    t.filter = new_filter(t.id, p, stamp_s, sigma);
    t.evidence = evidence;
    t.hits = 1;
    t.scored_s = stamp_s;
    t.pair_hits = pair ? 1 : 0;
    t.standing_pair_hits = standing ? 1 : 0;
    t.zone_pair_hits = pair && in_zone(p) ? 1 : 0;
    t.born_m = p;
    t.legs_now = pair ? 2 : 1;
    tracks_.push_back(t);
    return t.id;
  };
  std::vector<std::pair<double, std::pair<int, int>>> pairs;
  for (std::size_t i = 0; i < legs.size(); ++i)
    for (std::size_t j = i + 1; j < legs.size(); ++j) {
      if (used(int(i)) || used(int(j)) || legs[i].carry_only || legs[j].carry_only) continue;
      const double d2 = (legs[i].position_m - legs[j].position_m).squaredNorm();
      if (d2 <= pair2 && capped(legs[i].score) + capped(legs[j].score) > 0)
        pairs.push_back({d2, {int(i), int(j)}});
    }
  std::sort(pairs.begin(), pairs.end());
  for (const auto& [d2, ij] : pairs) {
    const auto [i, j] = ij;
    if (used(i) || used(j)) continue;
    const auto& li = legs[std::size_t(i)];
    const auto& lj = legs[std::size_t(j)];
    const Eigen::Vector2d mid = 0.5 * (li.position_m + lj.position_m);
    if (!free_here(mid)) continue;
    const auto id = birth(mid, c.pair_sigma_m, capped(li.score) + capped(lj.score), true,
                          standing_shape(li, lj));
    out.person_of_leg[std::size_t(i)] = out.person_of_leg[std::size_t(j)] = id;
  }
  for (std::size_t i = 0; i < legs.size(); ++i) {
    if (used(int(i)) || legs[i].carry_only || legs[i].score < c.single_birth_score_min) continue;
    if (!free_here(legs[i].position_m)) continue;
    out.person_of_leg[i] = birth(legs[i].position_m, c.single_sigma_m,
                                 c.single_weight * capped(legs[i].score), false, false);
  }

  for (const auto& t : tracks_)
    if (t.reported && stamp_s - t.filter.last_update_s <= c.report_coast_s)
      out.reported.push_back(t.id);
  return out;
}

}  // namespace fieldlidar::people
