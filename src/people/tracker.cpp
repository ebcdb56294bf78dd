#include "fieldlidar/people/tracker.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/Dense>

#include "fieldlidar/core/segment_distance.hpp"
#include "fieldlidar/people/assignment.hpp"

namespace fieldlidar::people {

void kalman_predict(Track& t, double dt, double accel_sigma) {
  // seed 000: A = [[1,T,0,0],[0,1,0,0],[0,0,1,T],[0,0,0,1]]
  Eigen::Matrix4d a = Eigen::Matrix4d::Identity();
  a(0, 1) = dt;
  a(2, 3) = dt;
  // Q of a piecewise-constant white acceleration per axis.
  const double q = accel_sigma * accel_sigma;
  Eigen::Matrix2d qa;
  qa << dt * dt * dt * dt / 4, dt * dt * dt / 2, dt * dt * dt / 2, dt * dt;
  Eigen::Matrix4d qm = Eigen::Matrix4d::Zero();
  qm.block<2, 2>(0, 0) = q * qa;
  qm.block<2, 2>(2, 2) = q * qa;
  t.state = a * t.state;
  t.covariance = a * t.covariance * a.transpose() + qm;
  t.stamp_s += dt;
}

void kalman_update(Track& t, const Eigen::Vector2d& z, double sigma) {
  Eigen::Matrix<double, 2, 4> h = Eigen::Matrix<double, 2, 4>::Zero();
  h(0, 0) = 1;
  h(1, 2) = 1;
  const Eigen::Matrix2d r = Eigen::Matrix2d::Identity() * sigma * sigma;
  const Eigen::Matrix2d s = h * t.covariance * h.transpose() + r;
  const Eigen::Matrix<double, 4, 2> k = t.covariance * h.transpose() * s.inverse();
  t.state += k * (z - h * t.state);
  const Eigen::Matrix4d ikh = Eigen::Matrix4d::Identity() - k * h;
  // Joseph form keeps P symmetric positive definite.
  t.covariance = ikh * t.covariance * ikh.transpose() + k * r * k.transpose();
}

PersonTracker::PersonTracker(const TrackerConfig& config) : config_(config) {}

const Track* PersonTracker::find(std::uint32_t id) const {
  for (const auto& t : tracks_)
    if (t.id == id) return &t;
  return nullptr;
}

bool PersonTracker::select_target(std::uint32_t id) {
  const Track* t = find(id);
  if (!t || !t->confirmed) return false;
  target_id_ = id;
  target_last_m_ = t->position();
  target_last_v_ = t->velocity();
  target_last_s_ = t->stamp_s;
  note_others(*t);
  return true;
}

std::optional<std::uint32_t> PersonTracker::select_nearest(const Eigen::Vector2d& point_m) {
  const Track* best = nullptr;
  for (const auto& t : tracks_)
    if (t.confirmed && t.missed_frames == 0 &&
        (!best || (t.position() - point_m).norm() < (best->position() - point_m).norm()))
      best = &t;
  if (!best) return std::nullopt;
  select_target(best->id);
  return best->id;
}

const Track* PersonTracker::target() const {
  if (!target_id_) return nullptr;
  const Track* t = find(*target_id_);
  if (!t || t->missed_frames > config_.coast_frames) return nullptr;
  return t;
}

const Track* PersonTracker::reacquisition_candidate(double stamp_s) const {
  const double lost_s = stamp_s - target_last_s_;
  const double radius =
      std::min(config_.reacquire_max_radius_m,
               config_.reacquire_radius_m + config_.reacquire_walk_speed_m_s * lost_s);
  // The lost track's straight-on path: where it was, to where it would be had it walked on.
  const Eigen::Vector2d a = target_last_m_, b = a + target_last_v_ * lost_s;
  const auto off_path = [&](const Eigen::Vector2d& p) { return point_segment_distance(p, a, b); };
  const Track* best = nullptr;
  for (const auto& c : tracks_) {
    if (!may_reacquire(c) || (c.position() - target_last_m_).norm() > radius) continue;
    if (!best || off_path(c.position()) < off_path(best->position())) best = &c;
  }
  return best;
}

void PersonTracker::note_others(const Track& target) {
  others_at_loss_.clear();
  for (const auto& o : tracks_)
    if (o.id != target.id && (o.position() - target.position()).norm() > config_.reacquire_radius_m)
      others_at_loss_.push_back(o.id);
}

bool walks(const Track& t, const TrackerConfig& c) {
  return t.streak >= c.reacquire_min_streak && t.velocity().norm() >= c.reacquire_min_speed_m_s &&
         (t.position() - t.born_m).norm() >= c.reacquire_min_walk_m;
}

bool PersonTracker::may_reacquire(const Track& c) const {
  if (!target_id_ || c.id == *target_id_ || !c.confirmed || c.missed_frames != 0 ||
      std::find(others_at_loss_.begin(), others_at_loss_.end(), c.id) != others_at_loss_.end())
    return false;
  return walks(c, config_);
}

bool PersonTracker::reacquire(std::uint32_t id) {
  if (!target_lost()) return false;
  const auto it =
      std::find_if(tracks_.begin(), tracks_.end(), [&](const Track& t) { return t.id == id; });
  if (it == tracks_.end() || !may_reacquire(*it)) return false;
  take_as_target(id);
  return true;
}

bool PersonTracker::retake(std::uint32_t id) {
  if (!target_lost() || id == *target_id_) return false;
  const auto it =
      std::find_if(tracks_.begin(), tracks_.end(), [&](const Track& t) { return t.id == id; });
  if (it == tracks_.end() || it->missed_frames != 0) return false;
  it->confirmed = true;
  take_as_target(id);
  return true;
}

void PersonTracker::take_as_target(std::uint32_t id) {
  const std::uint32_t target = *target_id_;
  std::erase_if(tracks_, [&](const Track& t) { return t.id == target; });
  for (auto& t : tracks_)
    if (t.id == id) {
      t.id = target;
      target_last_m_ = t.position();
      target_last_v_ = t.velocity();
      target_last_s_ = t.last_update_s;
    }
}

TrackerUpdate PersonTracker::update(double stamp_s, std::span<const Eigen::Vector2d> dets) {
  if (started_ && stamp_s < stamp_s_)
    throw std::invalid_argument("PersonTracker: frame time " + std::to_string(stamp_s) +
                                " s is before the previous " + std::to_string(stamp_s_) + " s");
  const double dt = started_ ? stamp_s - stamp_s_ : 0.0;
  started_ = true;
  stamp_s_ = stamp_s;
  for (auto& t : tracks_) kalman_predict(t, dt, config_.accel_sigma_m_s2);
  // A target lost longer than target_reattach_s is only taken again by a confirmed
  // re-acquisition: its coasting track goes (see TrackerConfig).
  if (target_id_ && stamp_s - target_last_s_ > config_.target_reattach_s)
    std::erase_if(tracks_, [&](const Track& t) { return t.id == *target_id_; });

  // Gated Mahalanobis cost of each (track, detection).
  const double r2 = config_.measurement_sigma_m * config_.measurement_sigma_m;
  Eigen::MatrixXd cost =
      Eigen::MatrixXd::Constant(Eigen::Index(tracks_.size()), Eigen::Index(dets.size()),
                                std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < tracks_.size(); ++i) {
    const auto& t = tracks_[i];
    Eigen::Matrix2d s;
    s << t.covariance(0, 0) + r2, t.covariance(0, 2), t.covariance(2, 0), t.covariance(2, 2) + r2;
    const Eigen::Matrix2d s_inv = s.inverse();
    for (std::size_t j = 0; j < dets.size(); ++j) {
      const Eigen::Vector2d d = dets[j] - t.position();
      const double m2 = d.dot(s_inv * d);
      if (m2 <= config_.gate_chi2 && d.norm() <= config_.gate_max_m)
        // Confirmed tracks are preferred over tentative ones for a contested detection.
        cost(Eigen::Index(i), Eigen::Index(j)) = m2 + (t.confirmed ? 0.0 : config_.gate_chi2);
    }
  }
  const auto assigned = solve_assignment(cost);

  TrackerUpdate result;
  result.track_of_detection.assign(dets.size(), -1);
  for (std::size_t i = 0; i < tracks_.size(); ++i) {
    auto& t = tracks_[i];
    if (assigned[i] < 0) {
      ++t.missed_frames;
      t.streak = 0;
      continue;
    }
    kalman_update(t, dets[std::size_t(assigned[i])], config_.measurement_sigma_m);
    const Eigen::Vector2d v = t.velocity();
    if (v.norm() > config_.max_speed_m_s) {
      const Eigen::Vector2d vc = v * (config_.max_speed_m_s / v.norm());
      t.state[1] = vc.x();
      t.state[3] = vc.y();
    }
    ++t.hits;
    ++t.streak;
    t.missed_frames = 0;
    t.last_update_s = stamp_s;
    if (t.hits >= config_.confirm_hits) t.confirmed = true;
    result.track_of_detection[std::size_t(assigned[i])] = t.id;
    if (target_id_ && t.id == *target_id_) result.target_updated = true;
  }

  // Deletion.
  std::erase_if(tracks_, [&](const Track& t) {
    const double missing = stamp_s - t.last_update_s;
    return t.confirmed ? missing > config_.delete_after_miss_s
                       : missing > config_.tentative_max_miss_s;
  });

  // Birth: every unused detection starts a tentative track at rest.
  for (std::size_t j = 0; j < dets.size(); ++j) {
    if (result.track_of_detection[j] >= 0 || !dets[j].allFinite()) continue;
    const bool duplicate = std::any_of(tracks_.begin(), tracks_.end(), [&](const Track& o) {
      return o.missed_frames == 0 &&
             (o.position() - dets[j]).norm() < config_.birth_min_separation_m;
    });
    if (duplicate) continue;
    Track t;
    t.id = next_id_++;
    t.state << dets[j].x(), 0, dets[j].y(), 0;
    const double ps = config_.measurement_sigma_m * config_.measurement_sigma_m;
    const double vs = config_.initial_speed_sigma_m_s * config_.initial_speed_sigma_m_s;
    t.covariance = Eigen::Vector4d(ps, vs, ps, vs).asDiagonal();
    t.hits = 1;
    t.last_update_s = t.stamp_s = t.born_s = stamp_s;
    t.born_m = dets[j];
    t.confirmed = config_.confirm_hits <= 1;
    result.track_of_detection[j] = t.id;
    tracks_.push_back(t);
  }

  // Target bookkeeping and re-acquisition after a loss (occlusion, a missed turn).
  if (target_id_) {
    const auto it = std::find_if(tracks_.begin(), tracks_.end(),
                                 [&](const Track& t) { return t.id == *target_id_; });
    const bool tracked = it != tracks_.end() && it->missed_frames <= config_.coast_frames;
    if (it != tracks_.end() && it->missed_frames == 0) {
      target_last_m_ = it->position();
      target_last_v_ = it->velocity();
      target_last_s_ = stamp_s;
      note_others(*it);
    } else if (!tracked && stamp_s - target_last_s_ <= config_.reacquire_window_s) {
      if (const Track* best = reacquisition_candidate(stamp_s)) {
        const std::uint32_t old_id = best->id;
        take_as_target(old_id);  // invalidates `best` and `it`
        for (auto& d : result.track_of_detection)
          if (d == old_id) d = *target_id_;
        result.target_updated = true;
      }
    }
  }
  return result;
}

}  // namespace fieldlidar::people
