#pragma once
// A stem's diameter from its silhouette in a sweep (sensor at the origin), and the per-ring index
// of returns it needs to tell a free edge from one hidden by something nearer.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <iterator>
#include <limits>
#include <numbers>
#include <span>
#include <utility>
#include <vector>

#include "fieldlidar/core/point_cloud.hpp"
#include "fieldlidar/forest/trunks.hpp"

namespace fieldlidar::forest {

// Every return of a sweep by ring, in azimuth order: what lies just beside a stem's edge.
class RingIndex {
 public:
  explicit RingIndex(const PointCloud& cloud) {
    for (std::size_t i = 0; i < cloud.size(); ++i) {
      const auto& p = cloud.points[i];
      if (!p.is_valid() || p.ring == Point::kNoRing) continue;
      if (p.ring >= rings_.size()) rings_.resize(p.ring + 1);
      rings_[p.ring].emplace_back(std::atan2(p.y, p.x), std::hypot(p.x, p.y));
    }
    steps_.resize(rings_.size(), 0.0);
    std::vector<double> gaps;
    for (std::size_t k = 0; k < rings_.size(); ++k) {
      auto& r = rings_[k];
      std::sort(r.begin(), r.end());
      gaps.clear();
      for (std::size_t j = 1; j < r.size(); ++j) gaps.push_back(r[j].first - r[j - 1].first);
      if (gaps.empty()) continue;
      std::nth_element(gaps.begin(), gaps.begin() + gaps.size() / 2, gaps.end());
      steps_[k] = gaps[gaps.size() / 2];
    }
  }
  /// Median azimuth step between neighbouring returns of a ring (rad); 0 when unknown.
  double step(int ring) const {
    return ring >= 0 && std::size_t(ring) < steps_.size() ? steps_[std::size_t(ring)] : 0.0;
  }
  /// Range of the nearest return beyond azimuth `az` (direction +1 or -1) within `window` rad;
  /// +inf when there is none (a free line of sight).
  double beside(int ring, double az, int direction, double window) const {
    double angle = 0, range = 0;
    if (!next_beyond(ring, az, direction, angle, range)) return 1e30;
    return angle <= window ? range : 1e30;
  }
  /// Whether the beam of the column next to azimuth `az` (direction +1 or -1, columns `step`
  /// apart) passed a stem whose edge return lies at az: it returned farther than `far_m`, or
  /// nothing at all (sky, out of range) unless a return nearer than far_m follows at once (a
  /// beam lost at the grazing edge of the stem beside an occluder). A return nearer than far_m
  /// (an occluder, the stem itself taken for ground, a shrub against it) leaves the edge open.
  bool passed_beside(int ring, double az, int direction, double step, double far_m) const {
    double angle = 1e30, range = 0.0;  // the first return beyond az (none: angle 1e30)
    if (!(step > 0)) return false;
    next_beyond(ring, az, direction, angle, range);
    if (angle <= 1.5 * step) return range > far_m;
    return !(angle <= 2.5 * step && range <= far_m);
  }

  /// Whether every return of `ring` within `half_width` rad of azimuth `az` lies beyond
  /// `far_m` (or there is none): the beam passed over what lies nearer at that bearing. False
  /// for a ring the cloud does not hold (nothing seen, nothing known).
  bool passed_over(int ring, double az, double half_width, double far_m) const {
    if (ring < 0 || std::size_t(ring) >= rings_.size() || rings_[ring].empty()) return false;
    const auto& r = rings_[ring];
    const double turn = 2 * std::numbers::pi, centre = std::remainder(az, turn);
    for (const double c : {centre, centre + turn, centre - turn}) {
      auto it = std::lower_bound(r.begin(), r.end(), std::make_pair(c - half_width, -1e30));
      for (; it != r.end() && it->first <= c + half_width; ++it)
        if (it->second <= far_m) return false;
    }
    return true;
  }

 private:
  // The first return of `ring` beyond azimuth az (direction +1 or -1), round the full turn: its
  // angle from az (0, 2 pi) and its range. False when the ring holds none.
  bool next_beyond(int ring, double az, int direction, double& angle, double& range) const {
    if (ring < 0 || std::size_t(ring) >= rings_.size() || rings_[ring].empty()) return false;
    const auto& r = rings_[ring];
    const double eps = 1e-7, turn = 2 * std::numbers::pi;
    az = std::remainder(az, turn);
    if (direction > 0) {
      auto it = std::upper_bound(r.begin(), r.end(), std::make_pair(az + eps, 1e30));
      if (it == r.end()) it = r.begin();
      angle = it->first - az;
      range = it->second;
    } else {
      auto it = std::lower_bound(r.begin(), r.end(), std::make_pair(az - eps, -1e30));
      if (it == r.begin()) it = r.end();
      --it;
      angle = az - it->first;
      range = it->second;
    }
    if (angle <= 0) angle += turn;
    return true;
  }

  std::vector<std::vector<std::pair<double, double>>> rings_;
  std::vector<double> steps_;
};

/// What the silhouette tells of a stem's radius near breast height.
struct SilhouetteRadius {
  double radius_m = 0.0;  ///< NaN when no scan line measures it
  /// The visible width of lines cut by an occluder: the second widest (0 with fewer than two).
  double lower_bound_m = 0.0;
  /// With no measure: the median over occluded lines of the free edge's angle from the fitted
  /// axis bearing, no less than lower_bound_m; NaN without such lines.
  double guess_m = std::numeric_limits<double>::quiet_NaN();
  std::size_t lines = 0;  ///< scan lines that measured it
};

/// Segments `segment_ids` of one stem whose centroid lies within dbh_window_m of breast height
/// above base_z; `axis` is the fitted cylinder (its bearing splits a line cut by an occluder).
/// When every such line is cut by an occluder, the stem's lines up to silhouette_far_window_m
/// from breast height that see both its edges free measure it instead of a guess.
SilhouetteRadius silhouette_radius(const PointCloud& cloud, std::span<const ScanSegment> segments,
                                   const RingIndex& rings, std::span<const std::size_t> segment_ids,
                                   const Cylinder& axis, double base_z, const TreeConfig& c);

}  // namespace fieldlidar::forest
