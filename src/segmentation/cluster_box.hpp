#pragma once
// Axis-aligned boxes of points and the squared distance of the Euclidean clustering's pair test.
// Internal to segmentation/.

#include <algorithm>

#include "cluster_common.hpp"

namespace fieldlidar::segmentation::detail {

using Xyz = ClusterPoint;

inline float squared_distance(const Xyz& a, const Xyz& b) {
  const float dx = a.x - b.x, dy = a.y - b.y, dz = a.z - b.z;
  return dx * dx + dy * dy + dz * dz;
}

/// Axis-aligned bounds of points (m).
struct Box {
  Xyz lo, hi;
  void add(const Xyz& p) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  static float gap(float lo_a, float hi_a, float lo_b, float hi_b) {
    return std::max({lo_b - hi_a, lo_a - hi_b, 0.f});
  }
  /// Squared distance between the boxes: no pair of their points is nearer.
  float gap2(const Box& o) const {
    const float dx = gap(lo.x, hi.x, o.lo.x, o.hi.x), dy = gap(lo.y, hi.y, o.lo.y, o.hi.y),
                dz = gap(lo.z, hi.z, o.lo.z, o.hi.z);
    return dx * dx + dy * dy + dz * dz;
  }
  /// Squared distance from p to the box: no point of the box is nearer to p.
  float gap2(const Xyz& p) const {
    const float dx = gap(p.x, p.x, lo.x, hi.x), dy = gap(p.y, p.y, lo.y, hi.y),
                dz = gap(p.z, p.z, lo.z, hi.z);
    return dx * dx + dy * dy + dz * dz;
  }
  /// Squared largest distance between the boxes: no pair of their points is farther apart.
  float span2(const Box& o) const {
    const float dx = std::max(hi.x - o.lo.x, o.hi.x - lo.x),
                dy = std::max(hi.y - o.lo.y, o.hi.y - lo.y),
                dz = std::max(hi.z - o.lo.z, o.hi.z - lo.z);
    return dx * dx + dy * dy + dz * dz;
  }
};

}  // namespace fieldlidar::segmentation::detail
