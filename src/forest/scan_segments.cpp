// Step 1 of seed 003: each scan line cut into segments of neighbouring returns; wide ones dropped.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <unordered_map>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/forest/trunks.hpp"

namespace fieldlidar::forest {
namespace {

bool usable(const Point& p, std::span<const std::uint8_t> excluded, std::size_t i,
            const ScanSegmentConfig& c, bool ranged) {
  if (!p.is_valid() || (!excluded.empty() && excluded[i])) return false;
  if (!ranged) return true;  // a plot file: coordinates are not sensor-centred
  const double r = std::hypot(p.x, p.y);
  return r >= c.min_range_m && r <= c.max_range_m;
}

void finish(const PointCloud& cloud, ScanSegment&& seg, const ScanSegmentConfig& c,
            std::vector<ScanSegment>& out, std::size_t min_points) {
  if (seg.indices.size() < min_points) return;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  Eigen::Vector2d lo(1e30, 1e30), hi(-1e30, -1e30);
  for (auto i : seg.indices) {
    const Eigen::Vector3d p = cloud.points[i].xyz().cast<double>();
    sum += p;
    lo = lo.cwiseMin(p.head<2>());
    hi = hi.cwiseMax(p.head<2>());
  }
  seg.centroid = sum / double(seg.indices.size());
  seg.width_m = (hi - lo).norm();
  if (seg.width_m > 2.0 * c.max_radius_m) return;
  out.push_back(std::move(seg));
}

double horizontal_range(const Point& p) {
  return std::hypot(p.x, p.y);
}

// Runs `a` and `b` of one ring (b after a in azimuth) are one stem seen on both sides of a nearer
// occluder: every return between them is nearer than both facing ends by occluder_gap_m, no beam
// is missed on the way, the facing ends lie at ranges a circle can give (within half their chord
// plus noise), each side comes nearer towards the occluder and the whole stays narrower than 2U.
bool bridges(const PointCloud& cloud, const std::vector<std::pair<double, std::uint32_t>>& order,
             std::size_t a_first, std::size_t a_last, std::size_t b_first, std::size_t b_last,
             const ScanSegmentConfig& c) {
  const double max_gap = c.max_azimuth_gap_deg * std::numbers::pi / 180.0;
  const auto& pa = cloud.points[order[a_last].second];
  const auto& pb = cloud.points[order[b_first].second];
  const double ra = horizontal_range(pa), rb = horizontal_range(pb);
  // Across the line of sight: the depth of a circle's near side varies by at most its radius,
  // and the facing ends are at least a radius apart only if they are a diameter apart.
  const double across = 0.5 * (ra + rb) *
                        std::abs(std::remainder(std::atan2(pb.y, pb.x) - std::atan2(pa.y, pa.x),
                                                2 * std::numbers::pi));
  if (std::abs(ra - rb) > 0.5 * across + c.bridge_range_tolerance_m) return false;
  const auto& p0 = cloud.points[order[a_first].second];
  const auto& p1 = cloud.points[order[b_last].second];
  if (std::hypot(p0.x - p1.x, p0.y - p1.y) > 2.0 * c.max_radius_m) return false;
  // Each side runs from the stem's free edge in towards its centre, behind the occluder: its
  // returns come nearer on the way (a whole small stem beside the occluder bulges instead).
  auto half_means = [&](std::size_t first, std::size_t last, double& outer, double& inner) {
    const std::size_t n = last - first + 1, h = n / 2;
    outer = inner = 0;
    for (std::size_t k = 0; k < h; ++k) {
      outer += horizontal_range(cloud.points[order[first + k].second]);
      inner += horizontal_range(cloud.points[order[last - k].second]);
    }
  };
  double outer = 0, inner = 0;
  if (a_last > a_first) {
    half_means(a_first, a_last, outer, inner);
    if (inner > outer) return false;
  }
  if (b_last > b_first) {
    half_means(b_first, b_last, inner, outer);
    if (inner > outer) return false;
  }
  for (std::size_t k = a_last + 1; k <= b_first; ++k) {
    if (std::remainder(order[k].first - order[k - 1].first, 2 * std::numbers::pi) > max_gap)
      return false;
    if (k < b_first &&
        horizontal_range(cloud.points[order[k].second]) > std::min(ra, rb) - c.occluder_gap_m)
      return false;
  }
  return true;
}

// A ring: returns in azimuth order, cut at missed returns and at jumps; the two sides of a stem
// split by a nearer occluder joined again.
void segment_ring(const PointCloud& cloud, int ring, std::vector<std::uint32_t>& idx,
                  const ScanSegmentConfig& c, std::vector<ScanSegment>& out) {
  std::vector<std::pair<double, std::uint32_t>> order;
  order.reserve(idx.size());
  for (auto i : idx) order.emplace_back(std::atan2(cloud.points[i].y, cloud.points[i].x), i);
  std::sort(order.begin(), order.end());
  const double max_gap = c.max_azimuth_gap_deg * std::numbers::pi / 180.0;
  // Whether neighbours j, k (k after j, across -pi/pi when k is first) are cut apart.
  const auto cut_between = [&](std::size_t j, std::size_t k) {
    const auto& a = cloud.points[order[j].second];
    const auto& b = cloud.points[order[k].second];
    double gap = order[k].first - order[j].first;
    if (gap < 0) gap += 2 * std::numbers::pi;
    const double limit = c.max_point_gap_m + c.point_gap_per_m * std::hypot(a.x, a.y);
    return gap > max_gap || (a.xyz() - b.xyz()).norm() > limit;
  };
  // A full turn has no start: a stem behind the sensor lies across -pi/pi. The runs start at
  // the first cut, the last one running on across -pi/pi.
  if (order.size() > 2 && !cut_between(order.size() - 1, 0)) {
    std::size_t first = 1;
    while (first < order.size() && !cut_between(first - 1, first)) ++first;
    if (first < order.size())
      std::rotate(order.begin(), order.begin() + std::ptrdiff_t(first), order.end());
  }
  // Runs as [first, last] positions in `order`.
  std::vector<std::pair<std::size_t, std::size_t>> runs;
  for (std::size_t k = 0; k < order.size(); ++k) {
    const bool cut = k == 0 || cut_between(k - 1, k);
    if (cut)
      runs.emplace_back(k, k);
    else
      runs.back().second = k;
  }
  std::vector<char> used(runs.size(), 0);
  for (std::size_t i = 0; i < runs.size(); ++i) {
    if (used[i]) continue;
    ScanSegment seg;
    seg.line = ring;
    std::size_t cur = i;
    for (std::size_t k = runs[i].first; k <= runs[i].second; ++k)
      seg.indices.push_back(order[k].second);
    for (bool joined = true; joined;) {
      joined = false;
      for (std::size_t m = cur + 2; m < runs.size() && m <= cur + 1 + c.max_bridged_runs; ++m) {
        if (used[m] || !bridges(cloud, order, runs[i].first, runs[cur].second, runs[m].first,
                                runs[m].second, c))
          continue;
        for (std::size_t k = runs[m].first; k <= runs[m].second; ++k)
          seg.indices.push_back(order[k].second);
        used[m] = 1;
        cur = m;
        joined = true;
        break;
      }
    }
    finish(cloud, std::move(seg), c, out, c.min_ring_points);
  }
}

// A horizontal slice of an unorganised cloud: 2D clusters by a grid of slice_link_m cells.
void segment_slice(const PointCloud& cloud, int line, const std::vector<std::uint32_t>& idx,
                   const ScanSegmentConfig& c, std::vector<ScanSegment>& out) {
  const double cell = c.slice_link_m;
  auto key = [](std::int64_t x, std::int64_t y) { return (x << 32) ^ (y & 0xffffffff); };
  std::unordered_map<std::int64_t, std::vector<std::uint32_t>> grid;
  grid.reserve(idx.size());
  for (auto i : idx)
    grid[key(std::int64_t(std::floor(cloud.points[i].x / cell)),
             std::int64_t(std::floor(cloud.points[i].y / cell)))]
        .push_back(i);
  std::unordered_map<std::int64_t, bool> seen;
  for (const auto& [k0, pts0] : grid) {
    if (seen[k0]) continue;
    ScanSegment seg;
    seg.line = line;
    std::vector<std::int64_t> todo{k0};
    seen[k0] = true;
    while (!todo.empty()) {
      const auto k = todo.back();
      todo.pop_back();
      const auto& pts = grid[k];
      seg.indices.insert(seg.indices.end(), pts.begin(), pts.end());
      const auto& p = cloud.points[pts.front()];
      const auto cx = std::int64_t(std::floor(p.x / cell)),
                 cy = std::int64_t(std::floor(p.y / cell));
      for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy) {
          const auto n = key(cx + dx, cy + dy);
          if (grid.count(n) && !seen[n]) {
            seen[n] = true;
            todo.push_back(n);
          }
        }
    }
    finish(cloud, std::move(seg), c, out, c.min_points);
  }
}

}  // namespace

std::vector<ScanSegment> segment_scan_lines(const PointCloud& cloud,
                                            std::span<const std::uint8_t> excluded,
                                            const ScanSegmentConfig& config) {
  if (!excluded.empty() && excluded.size() != cloud.size())
    throw Error("forest: exclusion flags (" + std::to_string(excluded.size()) +
                ") do not match the cloud (" + std::to_string(cloud.size()) + " points)");
  if (!(config.slice_m > 0) || !(config.slice_link_m > 0) || !(config.max_radius_m > 0))
    throw Error("forest: slice_m, slice_link_m and max_radius_m must be > 0");
  std::vector<ScanSegment> out;
  const bool rings = cloud.fields.ring && cloud.ring_count() > 0;
  std::unordered_map<int, std::vector<std::uint32_t>> lines;
  double z0 = 1e30;
  if (!rings)
    for (std::size_t i = 0; i < cloud.size(); ++i)
      if (usable(cloud.points[i], excluded, i, config, false))
        z0 = std::min(z0, double(cloud.points[i].z));
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const auto& p = cloud.points[i];
    if (!usable(p, excluded, i, config, rings)) continue;
    if (rings) {
      if (p.ring == Point::kNoRing) continue;
      lines[p.ring].push_back(std::uint32_t(i));
    } else {
      lines[int((p.z - z0) / config.slice_m)].push_back(std::uint32_t(i));
    }
  }
  std::vector<int> keys;
  for (const auto& [k, v] : lines) keys.push_back(k);
  std::sort(keys.begin(), keys.end());
  for (int k : keys) {
    if (rings)
      segment_ring(cloud, k, lines[k], config, out);
    else
      segment_slice(cloud, k, lines[k], config, out);
  }
  return out;
}

}  // namespace fieldlidar::forest
