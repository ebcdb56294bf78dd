// seed 002, step c: LOAM curvature over 5 neighbours each side on the same ring, edge and planar
// points by the threshold C, the strongest chosen per sector.

#include "fieldlidar/odometry/features.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace fieldlidar::odometry {

namespace {

/// Indices of the valid points of each ring, in scan order: ring r's are
/// index[start[r] .. start[r + 1]), their coordinates xyz[start[r] .. start[r + 1]). The copy in
/// ring order is filled in one pass over the cloud: read ring by ring from the cloud, a VLP-16
/// sweep's every 16th point, each in another cache line, made the whole cloud pass through the
/// cache once per ring.
struct RingLists {
  std::vector<std::uint32_t> start, index;
  std::vector<Eigen::Vector3f> xyz;
  std::size_t rings() const { return start.empty() ? 0 : start.size() - 1; }
  std::span<const std::uint32_t> ring(std::size_t r) const {
    return {index.data() + start[r], index.data() + start[r + 1]};
  }
  std::span<const Eigen::Vector3f> points(std::size_t r) const {
    return {xyz.data() + start[r], xyz.data() + start[r + 1]};
  }
};

RingLists ring_lists(const PointCloud& cloud, std::span<const std::uint16_t> rings,
                     std::span<const std::uint8_t> allowed) {
  // Two passes (count, then place) instead of one growing list per ring.
  RingLists out;
  std::vector<std::uint32_t>& count = out.start;
  std::vector<std::uint16_t> ring_of(cloud.size(), Point::kNoRing);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const auto r = rings[i];
    if (r == Point::kNoRing || !cloud.points[i].is_valid()) continue;
    if (!allowed.empty() && !allowed[i]) continue;
    if (r + 2u > count.size()) count.resize(r + 2u, 0);
    ++count[r + 1u];
    ring_of[i] = r;
  }
  for (std::size_t r = 1; r < count.size(); ++r) count[r] += count[r - 1];
  out.index.resize(count.empty() ? 0 : count.back());
  out.xyz.resize(out.index.size());
  std::vector<std::uint32_t> next(count.begin(), count.end());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (ring_of[i] == Point::kNoRing) continue;
    const std::uint32_t j = next[ring_of[i]]++;
    out.index[j] = std::uint32_t(i);
    out.xyz[j] = cloud.points[i].xyz();
  }
  return out;
}

/// Per-ring work arrays, kept by the caller across rings.
struct RingScratch {
  std::vector<float> r, gaps;
  std::vector<std::uint8_t> bad;
};

/// Curvature of each position of one ring (points `p` in scan order), -1 where the window is
/// short or unreliable.
void ring_curvature(std::span<const Eigen::Vector3f> p, int n, const FeatureConfig* cfg,
                    std::vector<float>& c, RingScratch& scratch) {
  const int m = int(p.size());
  c.assign(m, -1.f);
  if (m < 2 * n + 1) return;
  // Squared lengths first, their roots and quotients then four at a time (the same float
  // operations as norm() and the division per point: the sqrt and div latencies were most of
  // the time here).
  using Map = Eigen::Map<Eigen::ArrayXf>;
  auto& r = scratch.r;
  auto& gaps = scratch.gaps;
  auto& bad = scratch.bad;
  r.resize(m);
  for (int k = 0; k < m; ++k) r[k] = p[k].squaredNorm();
  Map(r.data(), m) = Map(r.data(), m).sqrt();
  // sum_j (X_k - X_j) over the 2n neighbours = (2n + 1) X_k - (sum of the window), the window
  // sum kept by sliding.
  Eigen::Vector3f window = Eigen::Vector3f::Zero();
  for (int j = 0; j <= 2 * n; ++j) window += p[j];
  for (int k = n; k < m - n; ++k) {
    if (k > n) window += p[k + n] - p[k - n - 1];
    c[k] = (float(2 * n + 1) * p[k] - window).squaredNorm();
  }
  const int w = m - 2 * n;
  Map(c.data() + n, w) = Map(c.data() + n, w).sqrt() / ((2.f * n) * Map(r.data() + n, w));
  if (!cfg) return;
  // LOAM's unreliable points: the farther side of an occlusion, surfaces parallel to the beam.
  bad.assign(m, 0);
  gaps.resize(m - 1);  // gaps[k] = |p[k+1] - p[k]|
  for (int k = 0; k + 1 < m; ++k) gaps[k] = (p[k + 1] - p[k]).squaredNorm();
  Map(gaps.data(), m - 1) = Map(gaps.data(), m - 1).sqrt();
  for (int k = 0; k + 1 < m; ++k) {
    const float gap = gaps[k];
    const float lim = std::max(float(cfg->max_neighbour_gap_m),
                               float(cfg->occlusion_ratio) * std::min(r[k], r[k + 1]));
    if (gap <= lim) continue;
    const float dr = r[k + 1] - r[k];
    if (dr > cfg->occlusion_ratio * r[k]) {  // k+1 farther: its side is occluded
      for (int j = k + 1; j <= std::min(m - 1, k + n); ++j) bad[j] = 1;
    } else if (-dr > cfg->occlusion_ratio * r[k + 1]) {
      for (int j = std::max(0, k - n + 1); j <= k; ++j) bad[j] = 1;
    } else {  // a hole in the ring: neither side has a full window
      for (int j = std::max(0, k - n + 1); j <= std::min(m - 1, k + n); ++j) bad[j] = 1;
    }
  }
  const double min_r = cfg->min_range_m, max_r = cfg->max_range_m;
  for (int k = 1; k + 1 < m; ++k) {
    const float lim = 0.02f * r[k];
    if (gaps[k] > lim && gaps[k - 1] > lim) bad[k] = 1;
    if (r[k] < min_r || r[k] > max_r) bad[k] = 1;
  }
  for (int k = 0; k < m; ++k)
    if (bad[k]) c[k] = -1.f;
}

/// Sort key of position k with curvature c >= 0: ascending keys give ascending c (the bits of a
/// non-negative float order as the float), ties by k; with `descending`, descending c, ties by k.
std::uint64_t sort_key(float c, int k, bool descending) {
  std::uint32_t bits;
  std::memcpy(&bits, &c, sizeof bits);
  if (descending) bits = ~bits;
  return (std::uint64_t(bits) << 32) | std::uint32_t(k);
}

/// Visits the positions of the first `limit` keys in ascending order until `visit` returns false.
/// Only what is visited gets sorted: chunks picked by nth_element, each twice the last, so a
/// sector whose first few candidates suffice costs one linear pass.
template <class Visit>
void visit_sorted(std::vector<std::uint64_t>& keys, std::size_t limit, std::size_t chunk,
                  Visit visit) {
  const std::size_t end = std::min(limit, keys.size());
  for (std::size_t done = 0; done < end; chunk *= 2) {
    const std::size_t next = std::min(end, done + std::max<std::size_t>(chunk, 1));
    const auto first = keys.begin() + long(done), last = keys.begin() + long(next);
    if (next < keys.size()) std::nth_element(first, last, keys.end());
    std::sort(first, last);
    for (auto it = first; it != last; ++it)
      if (!visit(int(std::uint32_t(*it)))) return;
    done = next;
  }
}

}  // namespace

std::vector<float> curvature(const PointCloud& cloud, std::span<const std::uint16_t> rings,
                             int neighbours) {
  std::vector<float> out(cloud.size(), -1.f);
  std::vector<float> c;
  RingScratch scratch;
  const RingLists lists = ring_lists(cloud, rings, {});
  for (std::size_t r = 0; r < lists.rings(); ++r) {
    const auto idx = lists.ring(r);
    ring_curvature(lists.points(r), neighbours, nullptr, c, scratch);
    for (std::size_t k = 0; k < idx.size(); ++k) out[idx[k]] = c[k];
  }
  return out;
}

Features extract_features(const PointCloud& cloud, std::span<const std::uint16_t> rings,
                          std::span<const std::uint8_t> allowed,
                          std::span<const std::uint8_t> plane_only, const FeatureConfig& config) {
  Features f;
  std::vector<Eigen::Vector3f> strong_e, weak_e, strong_p, weak_p;
  const float C = float(config.curvature_threshold);
  const int n = config.neighbours;
  std::vector<float> c;
  std::vector<std::uint64_t> edge_order, plane_order;
  std::vector<std::uint8_t> picked;
  RingScratch scratch;
  const RingLists lists = ring_lists(cloud, rings, allowed);
  // Every map_plane_stride-th planar point and the neighbours of the chosen ones: about half.
  f.plane_candidates.reserve(lists.index.size() / 2);
  for (std::size_t r = 0; r < lists.rings(); ++r) {
    const auto idx = lists.ring(r);
    const auto pts = lists.points(r);
    ring_curvature(pts, n, &config, c, scratch);
    const int m = int(idx.size());
    picked.assign(m, 0);
    // Marks the neighbours of a chosen point so that features spread along the ring.
    auto suppress = [&](int k) {
      for (int d = -n; d <= n; ++d) {
        const int j = k + d;
        if (j < 0 || j >= m) continue;
        if ((pts[std::size_t(j)] - pts[std::size_t(k)]).squaredNorm() < 0.05f) picked[j] = 1;
      }
    };
    for (int s = 0; s < config.sectors; ++s) {
      const int b = m * s / config.sectors, e = m * (s + 1) / config.sectors;
      // Edges: the candidates with c >= C, strongest first; planes: 0 <= c < C, smallest first.
      edge_order.clear();
      plane_order.clear();
      for (int k = b; k < e; ++k) {
        if (c[k] >= C)
          edge_order.push_back(sort_key(c[k], k, true));
        else if (c[k] >= 0)
          plane_order.push_back(sort_key(c[k], k, false));
      }
      int taken = 0;
      visit_sorted(edge_order, 8 * std::size_t(config.edges_per_sector),
                   2 * std::size_t(config.edges_per_sector), [&](int k) {
                     if (taken >= config.edges_per_sector) return false;
                     if (picked[k] || (!plane_only.empty() && plane_only[idx[k]])) return true;
                     (c[k] >= (1 + C) / 2 ? strong_e : weak_e).push_back(pts[std::size_t(k)]);
                     suppress(k);
                     ++taken;
                     return true;
                   });
      taken = 0;
      visit_sorted(plane_order, 8 * std::size_t(config.planes_per_sector),
                   2 * std::size_t(config.planes_per_sector), [&](int k) {
                     if (taken >= config.planes_per_sector) return false;
                     if (picked[k]) return true;
                     (c[k] < C / 2 ? strong_p : weak_p).push_back(pts[std::size_t(k)]);
                     suppress(k);
                     ++taken;
                     return true;
                   });
    }
    int stride = 0;
    for (int k = 0; k < m; ++k) {
      if (c[k] < 0) continue;
      const bool edge = c[k] >= C && (plane_only.empty() || !plane_only[idx[k]]);
      if (edge)
        f.edge_candidates.push_back(pts[std::size_t(k)]);
      else if (c[k] < C && (picked[k] || ++stride % config.map_plane_stride == 0))
        f.plane_candidates.push_back(pts[std::size_t(k)]);
    }
  }
  f.edges = std::move(strong_e);
  f.edges.insert(f.edges.end(), weak_e.begin(), weak_e.end());
  f.planes = std::move(strong_p);
  f.planes.insert(f.planes.end(), weak_p.begin(), weak_p.end());
  return f;
}

void thin_by_spacing(std::vector<Eigen::Vector3f>& points, double spacing_m) {
  if (spacing_m <= 0 || points.size() < 2) return;
  // The cubes seen, in an open-addressing set (linear probing, at most half full) of their keys:
  // 21 bits per axis, so +-2^20 cubes around the sensor.
  std::size_t size = 64;
  while (size < 2 * points.size()) size *= 2;
  constexpr std::uint64_t kEmpty = ~std::uint64_t(0);
  std::vector<std::uint64_t> table(size, kEmpty);
  const float inv = float(1.0 / spacing_m);
  const auto cube = [inv](float v) {
    const float s = v * inv;
    const auto i = std::int64_t(s) - std::int64_t(s < float(std::int64_t(s)));  // floor
    return std::uint64_t(std::clamp<std::int64_t>(i + (1 << 20), 0, (1 << 21) - 1));
  };
  std::size_t kept = 0;
  for (const auto& p : points) {
    if (!p.allFinite()) continue;
    const std::uint64_t key = (cube(p.x()) << 42) | (cube(p.y()) << 21) | cube(p.z());
    std::size_t i = std::size_t((key * 0x9E3779B97F4A7C15ull) >> 20) & (size - 1);
    while (table[i] != kEmpty && table[i] != key) i = (i + 1) & (size - 1);
    if (table[i] == key) continue;
    table[i] = key;
    points[kept++] = p;
  }
  points.resize(kept);
}

}  // namespace fieldlidar::odometry
