// Lazy 8-connected Dijkstra from the goal (the obstacle-aware heuristic of Hybrid A*) on a
// downsampled, padded copy of the planning map, with cells too tight for the footprint's centre
// blocked.

#include "obstacle_heuristic.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>

namespace fieldlidar::planning {

std::vector<std::uint8_t> centre_blocked_cells(const PlanningMap& map, double radius_m) {
  const GridGeometry& g = map.geometry();
  const double res = g.resolution_m;
  std::vector<std::uint8_t> out(g.cell_count(), 0);
  // Sample points 1/8 cell apart (borders included): any point of the cell is within `slack` of
  // one, and the distance to the blocked set is 1-Lipschitz.
  constexpr int kSamples = 9;
  const double s = res / (kSamples - 1);
  const double slack = s * std::sqrt(0.5);
  const double limit = radius_m - slack;
  const int reach = int(std::ceil(radius_m / res)) + 1;
  std::vector<std::pair<double, double>> near;  // blocked squares' centres, relative (m)
  for (int iy = 0; iy < g.height; ++iy)
    for (int ix = 0; ix < g.width; ++ix) {
      const std::size_t i = g.linear_index(ix, iy);
      if (map.blocked(i)) {
        out[i] = 1;
        continue;
      }
      // the cell centre alone is at least this far from every blocked square
      if (limit <= 0.0 || map.obstacle_distance_m(i) - res * std::sqrt(0.5) >= limit) continue;
      near.clear();
      for (int dy = -reach; dy <= reach; ++dy)
        for (int dx = -reach; dx <= reach; ++dx) {
          const int x = ix + dx, y = iy + dy;
          if (!g.contains(x, y) || map.blocked(g.linear_index(x, y)))
            near.emplace_back(dx * res, dy * res);
        }
      // Distance from a point (relative to the cell centre) to the nearest blocked square.
      auto clear_of_all = [&](double px, double py) {
        for (const auto& [cx, cy] : near) {
          const double ex = std::max(0.0, std::abs(px - cx) - 0.5 * res);
          const double ey = std::max(0.0, std::abs(py - cy) - 0.5 * res);
          if (ex * ex + ey * ey < limit * limit) return false;
        }
        return true;
      };
      bool all_tight = true;
      for (int k = 0; k < kSamples * kSamples && all_tight; ++k) {
        // corners and edges first: where a point is clear, it usually is there
        const int a = k / kSamples, b = k % kSamples;
        const int sx = (a % 2 == 0) ? a / 2 : kSamples - 1 - a / 2;
        const int sy = (b % 2 == 0) ? b / 2 : kSamples - 1 - b / 2;
        if (clear_of_all(-0.5 * res + sx * s, -0.5 * res + sy * s)) all_tight = false;
      }
      out[i] = all_tight;
    }
  return out;
}

void ObstacleHeuristic::push(float key_m, std::uint32_t i) {
  // monotone for key_m >= 0; a key rounded below the last popped one is taken as equal to it
  const std::uint32_t key = std::max(std::bit_cast<std::uint32_t>(key_m), last_key_);
  buckets_[std::bit_width(key ^ last_key_)].push_back((std::uint64_t(key) << 32) | i);
  ++queued_;
}

bool ObstacleHeuristic::pop(std::uint32_t* cell) {
  if (queued_ == 0) return false;
  if (buckets_[0].empty()) {
    int b = 1;
    while (buckets_[b].empty()) ++b;
    std::uint64_t least = buckets_[b][0];
    for (std::uint64_t e : buckets_[b]) least = std::min(least, e);
    last_key_ = std::uint32_t(least >> 32);
    for (std::uint64_t e : buckets_[b])
      buckets_[std::bit_width(std::uint32_t(e >> 32) ^ last_key_)].push_back(e);
    buckets_[b].clear();
  }
  *cell = std::uint32_t(buckets_[0].back() & 0xffffffffu);
  buckets_[0].pop_back();
  --queued_;
  return true;
}

float ObstacleHeuristic::focus_distance(long x, long y) const {
  if (focus_x_ < 0) return 0.0f;
  const long dx = std::abs(x - focus_x_), dy = std::abs(y - focus_y_);
  // octile distance: the shortest 8-connected path on an open grid; less a float's rounding
  return float(double(std::max(dx, dy)) + (std::numbers::sqrt2 - 1.0) * double(std::min(dx, dy))) *
         float(coarse_res_m_) * min_mult_ * 0.99999f;
}

void ObstacleHeuristic::reset(const PlanningMap& map, long goal_cell, long focus_cell,
                              double tau_weight, int downsample) {
  const GridGeometry& g = map.geometry();
  const int f = std::max(1, downsample);
  if (&map != map_ || f != factor_ || tau_weight != tau_weight_) {
    map_ = &map;
    factor_ = f;
    tau_weight_ = tau_weight;
    cw_ = (g.width + f - 1) / f;
    ch_ = (g.height + f - 1) / f;
    pw_ = cw_ + 2;
    coarse_res_m_ = g.resolution_m * f;
    const std::size_t n = std::size_t(pw_) * (ch_ + 2);
    half_mult_.assign(n, std::numeric_limits<float>::infinity());
    blocked_.assign(n, 1);
    const double inscribed =
        0.5 * std::min(map.robot().length_m, map.robot().width_m) + map.config().footprint_margin_m;
    const std::vector<std::uint8_t> tight = centre_blocked_cells(map, inscribed);
    for (int iy = 0; iy < g.height; ++iy)
      for (int ix = 0; ix < g.width; ++ix) {
        const std::size_t i = g.linear_index(ix, iy);
        if (tight[i]) continue;
        const std::size_t c = std::size_t(iy / f + 1) * pw_ + ix / f + 1;
        blocked_[c] = 0;
        half_mult_[c] =
            std::min(half_mult_[c], 0.5f * (1.0f + float(tau_weight) * (1.0f - map.tau(i))));
      }
    min_mult_ = std::numeric_limits<float>::infinity();
    for (std::size_t c = 0; c < n; ++c)
      if (!blocked_[c]) min_mult_ = std::min(min_mult_, 2.0f * half_mult_[c]);
    if (!std::isfinite(min_mult_)) min_mult_ = 1.0f;
    dist_.assign(n, std::numeric_limits<float>::infinity());
  } else {
    std::fill(dist_.begin(), dist_.end(), std::numeric_limits<float>::infinity());
  }
  closed_ = blocked_;
  for (auto& b : buckets_) b.clear();
  last_key_ = 0;
  queued_ = 0;
  settled_count_ = 0;
  const long fc = coarse_of(focus_cell);
  focus_x_ = fc < 0 ? -1 : fc % pw_;
  focus_y_ = fc < 0 ? -1 : fc / pw_;
  const long c = coarse_of(goal_cell);
  if (c < 0 || blocked_[std::size_t(c)]) return;
  dist_[std::size_t(c)] = 0.0f;
  push(focus_distance(c % pw_, c / pw_), std::uint32_t(c));
}

long ObstacleHeuristic::coarse_of(long cell) const {
  if (cell < 0) return -1;
  const int w = map_->geometry().width;
  const int ix = int(cell % w), iy = int(cell / w);
  return long(iy / factor_ + 1) * pw_ + ix / factor_ + 1;
}

double ObstacleHeuristic::cost_m(long cell, std::chrono::steady_clock::time_point deadline) {
  const long c = coarse_of(cell);
  if (c < 0) return std::numeric_limits<double>::infinity();
  const std::size_t target = std::size_t(c);
  if (blocked_[target]) return std::numeric_limits<double>::infinity();
  const float res = float(coarse_res_m_), diag = res * 1.41421356f;
  const long pw = pw_;
  const long offsets[8] = {1, -1, pw, -pw, pw + 1, pw - 1, -pw + 1, -pw - 1};
  const float lengths[8] = {res, res, res, res, diag, diag, diag, diag};
  const long dxs[8] = {1, -1, 0, 0, 1, -1, 1, -1}, dys[8] = {0, 0, 1, -1, 1, 1, -1, -1};
  int since_clock = 0;
  std::uint32_t top = 0;
  while (!(closed_[target] && dist_[target] < std::numeric_limits<float>::infinity()) &&
         pop(&top)) {
    if (++since_clock == 1024) {
      since_clock = 0;
      if (std::chrono::steady_clock::now() > deadline)
        return std::numeric_limits<double>::quiet_NaN();
    }
    const std::size_t i = top;
    if (closed_[i]) continue;
    closed_[i] = 1;
    ++settled_count_;
    const float d = dist_[i];
    const float hm = half_mult_[i];
    const long x = long(i) % pw, y = long(i) / pw;
    for (int k = 0; k < 8; ++k) {
      const std::size_t j = std::size_t(long(i) + offsets[k]);
      if (closed_[j]) continue;
      const float nd = d + lengths[k] * (hm + half_mult_[j]);
      if (nd < dist_[j]) {
        dist_[j] = nd;
        push(nd + focus_distance(x + dxs[k], y + dys[k]), std::uint32_t(j));
      }
    }
  }
  // Between cell centres; with downsampling, less the half-diagonal of a coarse cell so it stays a
  // lower bound for any point of the cell.
  if (!closed_[target] || !(dist_[target] < std::numeric_limits<float>::infinity()))
    return std::numeric_limits<double>::infinity();
  if (factor_ == 1) return double(dist_[target]);
  return std::max(0.0, double(dist_[target]) - 0.7072 * coarse_res_m_);
}

}  // namespace fieldlidar::planning
