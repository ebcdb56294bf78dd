#pragma once
/// \file CLEAR MOT scoring of tracked persons against annotated persons (Bernardin and
/// Stiefelhagen, "Evaluating Multiple Object Tracking Performance: The CLEAR MOT Metrics", 2008),
/// as the leg_tracker benchmarks score 2D person trackers.
///
/// Per frame: every last known correspondence (track id <-> truth id) whose track and truth
/// person are both present and closer than the gate is kept; the remaining tracks and truth
/// persons are matched by minimum total distance (Hungarian method) among pairs closer than the
/// gate. Unmatched truth persons are misses, unmatched tracks false positives. A match is an id
/// switch when its truth person was last matched to another track (the paper's mismatch) or,
/// as the leg_tracker benchmark also counts, when its track was last matched to another truth
/// person. Correspondences are remembered across frames until one side gets a new match.
/// MOTP = mean distance of the matches; MOTA = 1 - (misses + false positives + id switches) /
/// truth count. Positions in m, any one frame shared by truth and tracks.

#include <cstddef>
#include <cstdint>
#include <map>
#include <span>

#include <Eigen/Core>

namespace fieldlidar::people {

struct ClearMotConfig {
  /// A track matches a truth person only when strictly closer than this (m; the benchmarks: 0.75).
  double gate_m = 0.75;
  /// Also count a match whose track was last matched to another truth person as an id switch
  /// (the leg_tracker benchmark's scorer); false = only the paper's truth-side mismatches.
  bool count_track_side_switches = true;
};

/// One person in one frame: a truth annotation or a tracked person, with its id.
struct IdentifiedPoint {
  std::int64_t id = 0;
  Eigen::Vector2d position_m = Eigen::Vector2d::Zero();
};

/// Counts over frames (or of one frame).
struct ClearMotCounts {
  std::size_t frames = 0;
  std::size_t truth = 0;    ///< annotated persons scored
  std::size_t tracked = 0;  ///< tracked persons scored
  std::size_t matches = 0;
  std::size_t misses = 0;
  std::size_t false_positives = 0;
  std::size_t id_switches = 0;
  double distance_sum_m = 0;  ///< sum of the match distances

  /// 1 - (misses + false positives + id switches) / truth; without truth: 1 when there is no
  /// error, -infinity otherwise.
  double mota() const;
  /// Mean match distance (m); NaN without matches.
  double motp_m() const;
  /// matches / truth: the share of annotated persons reported; NaN without truth.
  double recall() const;
  /// false positives / frames; NaN without frames.
  double false_positives_per_frame() const;
  ClearMotCounts& operator+=(const ClearMotCounts& o);
};

class ClearMotScorer {
 public:
  explicit ClearMotScorer(const ClearMotConfig& config = {});

  /// Scores one frame and returns its counts (also added to totals()). Ids must be unique within
  /// `truth` and within `tracked` (fieldlidar::Error otherwise); positions finite.
  ClearMotCounts add_frame(std::span<const IdentifiedPoint> truth,
                           std::span<const IdentifiedPoint> tracked);

  const ClearMotCounts& totals() const { return totals_; }
  const ClearMotConfig& config() const { return config_; }

 private:
  ClearMotConfig config_;
  ClearMotCounts totals_;
  std::map<std::int64_t, std::int64_t> truth_of_track_;  ///< last known correspondences
};

}  // namespace fieldlidar::people
