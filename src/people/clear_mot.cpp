#include "fieldlidar/people/clear_mot.hpp"

#include <cmath>
#include <limits>
#include <string>
#include <unordered_map>
#include <vector>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/people/assignment.hpp"

namespace fieldlidar::people {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// Index of each id in `points`; a repeated id or a non-finite position is an Error.
std::unordered_map<std::int64_t, std::size_t> index_by_id(std::span<const IdentifiedPoint> points,
                                                          const char* what) {
  std::unordered_map<std::int64_t, std::size_t> out;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!points[i].position_m.allFinite())
      throw Error(std::string("CLEAR MOT: ") + what + " id " + std::to_string(points[i].id) +
                  " has a non-finite position");
    if (!out.emplace(points[i].id, i).second)
      throw Error(std::string("CLEAR MOT: ") + what + " id " + std::to_string(points[i].id) +
                  " appears twice in one frame");
  }
  return out;
}

}  // namespace

double ClearMotCounts::mota() const {
  const double errors = double(misses + false_positives + id_switches);
  if (truth == 0) return errors == 0 ? 1.0 : -std::numeric_limits<double>::infinity();
  return 1.0 - errors / double(truth);
}

double ClearMotCounts::motp_m() const {
  return matches ? distance_sum_m / double(matches) : kNaN;
}

double ClearMotCounts::recall() const {
  return truth ? double(matches) / double(truth) : kNaN;
}

double ClearMotCounts::false_positives_per_frame() const {
  return frames ? double(false_positives) / double(frames) : kNaN;
}

ClearMotCounts& ClearMotCounts::operator+=(const ClearMotCounts& o) {
  frames += o.frames;
  truth += o.truth;
  tracked += o.tracked;
  matches += o.matches;
  misses += o.misses;
  false_positives += o.false_positives;
  id_switches += o.id_switches;
  distance_sum_m += o.distance_sum_m;
  return *this;
}

ClearMotScorer::ClearMotScorer(const ClearMotConfig& config) : config_(config) {
  if (!(config_.gate_m > 0) || !std::isfinite(config_.gate_m))
    throw Error("CLEAR MOT: the gate must be a positive distance, got " +
                std::to_string(config_.gate_m));
}

ClearMotCounts ClearMotScorer::add_frame(std::span<const IdentifiedPoint> truth,
                                         std::span<const IdentifiedPoint> tracked) {
  const auto truth_index = index_by_id(truth, "truth");
  const auto track_index = index_by_id(tracked, "track");
  const double gate = config_.gate_m;
  auto dist = [&](std::size_t k, std::size_t t) {
    return (tracked[k].position_m - truth[t].position_m).norm();
  };

  // match_of_track[k] = truth index, or -1.
  std::vector<int> match_of_track(tracked.size(), -1);
  std::vector<char> truth_taken(truth.size(), 0);
  // 1. Last known correspondences still within the gate are kept.
  for (const auto& [track_id, truth_id] : truth_of_track_) {
    const auto k = track_index.find(track_id);
    const auto t = truth_index.find(truth_id);
    if (k == track_index.end() || t == truth_index.end()) continue;
    if (dist(k->second, t->second) < gate) {
      match_of_track[k->second] = int(t->second);
      truth_taken[t->second] = 1;
    }
  }
  // 2. Minimum-distance assignment of the rest, pairs beyond the gate forbidden.
  std::vector<std::size_t> free_tracks, free_truth;
  for (std::size_t k = 0; k < tracked.size(); ++k)
    if (match_of_track[k] < 0) free_tracks.push_back(k);
  for (std::size_t t = 0; t < truth.size(); ++t)
    if (!truth_taken[t]) free_truth.push_back(t);
  if (!free_tracks.empty() && !free_truth.empty()) {
    const double inf = std::numeric_limits<double>::infinity();
    Eigen::MatrixXd cost(Eigen::Index(free_tracks.size()), Eigen::Index(free_truth.size()));
    for (std::size_t r = 0; r < free_tracks.size(); ++r)
      for (std::size_t c = 0; c < free_truth.size(); ++c) {
        const double d = dist(free_tracks[r], free_truth[c]);
        cost(Eigen::Index(r), Eigen::Index(c)) = d < gate ? d : inf;
      }
    const auto assigned = solve_assignment(cost);
    for (std::size_t r = 0; r < free_tracks.size(); ++r)
      if (assigned[r] >= 0) {
        match_of_track[free_tracks[r]] = int(free_truth[std::size_t(assigned[r])]);
        truth_taken[free_truth[std::size_t(assigned[r])]] = 1;
      }
  }

  // 3. Counts and id switches against the correspondences known before this frame.
  ClearMotCounts c;
  c.frames = 1;
  c.truth = truth.size();
  c.tracked = tracked.size();
  std::unordered_map<std::int64_t, std::int64_t> track_of_truth;
  for (const auto& [track_id, truth_id] : truth_of_track_) track_of_truth[truth_id] = track_id;
  std::vector<std::pair<std::int64_t, std::int64_t>> new_pairs;
  for (std::size_t k = 0; k < tracked.size(); ++k) {
    if (match_of_track[k] < 0) {
      ++c.false_positives;
      continue;
    }
    const auto& gt = truth[std::size_t(match_of_track[k])];
    const std::int64_t track_id = tracked[k].id;
    ++c.matches;
    c.distance_sum_m += dist(k, std::size_t(match_of_track[k]));
    const auto prev_track = track_of_truth.find(gt.id);
    const auto prev_truth = truth_of_track_.find(track_id);
    const bool truth_side = prev_track != track_of_truth.end() && prev_track->second != track_id;
    const bool track_side = prev_truth != truth_of_track_.end() && prev_truth->second != gt.id;
    if (truth_side || (config_.count_track_side_switches && track_side)) ++c.id_switches;
    new_pairs.emplace_back(track_id, gt.id);
  }
  c.misses = c.truth - c.matches;

  // 4. Remember this frame's matches; an older pair loses both of its ends to them.
  for (const auto& [track_id, truth_id] : new_pairs) {
    truth_of_track_.erase(track_id);
    for (auto it = truth_of_track_.begin(); it != truth_of_track_.end();)
      it = it->second == truth_id ? truth_of_track_.erase(it) : std::next(it);
  }
  for (const auto& [track_id, truth_id] : new_pairs) truth_of_track_[track_id] = truth_id;
  totals_ += c;
  return c;
}

}  // namespace fieldlidar::people
