#pragma once
/// \file Pairing the poses of two timestamped trajectories by time, as `evo` associates TUM files.

#include <cstddef>
#include <utility>
#include <vector>

#include "fieldlidar/core/pose.hpp"

namespace fieldlidar {

/// Frame-indexed pose pairs of two trajectories.
struct MatchedPoses {
  std::vector<Pose> a, b;
  std::vector<std::pair<std::size_t, std::size_t>> indices;  ///< (index in a, index in b)
  double max_dt_s = 0.0;  ///< largest time difference of a pair (s)
};

/// For every pose of `a`, the pose of `b` nearest in time if within `max_dt_s`; each pose of `b`
/// is used at most once and the pairs keep the order of both trajectories. Throws Error for a
/// negative or NaN `max_dt_s`.
MatchedPoses match_by_time(const Trajectory& a, const Trajectory& b, double max_dt_s);

}  // namespace fieldlidar
