// Lazy 8-connected Dijkstra from the goal (the obstacle-aware heuristic of Hybrid A*) on a
// downsampled copy of the planning map.

#include "obstacle_heuristic.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fieldlidar::planning {

void ObstacleHeuristic::reset(const PlanningMap& map, long goal_cell, double tau_weight,
                              int downsample) {
  const GridGeometry& g = map.geometry();
  const int f = std::max(1, downsample);
  if (&map != map_ || f != factor_ || tau_weight != tau_weight_) {
    map_ = &map;
    factor_ = f;
    tau_weight_ = tau_weight;
    cw_ = (g.width + f - 1) / f;
    ch_ = (g.height + f - 1) / f;
    coarse_res_m_ = g.resolution_m * f;
    mult_.assign(std::size_t(cw_) * ch_, std::numeric_limits<float>::infinity());
    blocked_.assign(mult_.size(), 1);
    for (int iy = 0; iy < g.height; ++iy)
      for (int ix = 0; ix < g.width; ++ix) {
        const std::size_t i = g.linear_index(ix, iy);
        if (map.blocked(i)) continue;
        const std::size_t c = std::size_t(iy / f) * cw_ + ix / f;
        blocked_[c] = 0;
        mult_[c] = std::min(mult_[c], 1.0f + float(tau_weight) * (1.0f - map.tau(i)));
      }
  }
  dist_.assign(mult_.size(), std::numeric_limits<float>::infinity());
  settled_.assign(mult_.size(), 0);
  open_ = {};
  settled_count_ = 0;
  const long c = coarse_of(goal_cell);
  if (c < 0 || blocked_[std::size_t(c)]) return;
  dist_[std::size_t(c)] = 0.0f;
  open_.push({0.0f, std::uint32_t(c)});
}

long ObstacleHeuristic::coarse_of(long cell) const {
  if (cell < 0) return -1;
  const int w = map_->geometry().width;
  const int ix = int(cell % w), iy = int(cell / w);
  return long(iy / factor_) * cw_ + ix / factor_;
}

double ObstacleHeuristic::cost_m(long cell, std::chrono::steady_clock::time_point deadline) {
  const long c = coarse_of(cell);
  if (c < 0) return std::numeric_limits<double>::infinity();
  const std::size_t target = std::size_t(c);
  const float res = float(coarse_res_m_);
  static constexpr int kDx[8] = {1, -1, 0, 0, 1, 1, -1, -1};
  static constexpr int kDy[8] = {0, 0, 1, -1, 1, -1, 1, -1};
  int since_clock = 0;
  while (!settled_[target] && !open_.empty()) {
    if (++since_clock == 512) {
      since_clock = 0;
      if (std::chrono::steady_clock::now() > deadline)
        return std::numeric_limits<double>::quiet_NaN();
    }
    const auto [d, i] = open_.top();
    open_.pop();
    if (settled_[i]) continue;
    settled_[i] = 1;
    ++settled_count_;
    const int x = int(i % std::uint32_t(cw_)), y = int(i / std::uint32_t(cw_));
    const float mi = mult_[i];
    for (int k = 0; k < 8; ++k) {
      const int nx = x + kDx[k], ny = y + kDy[k];
      if (nx < 0 || ny < 0 || nx >= cw_ || ny >= ch_) continue;
      const std::size_t j = std::size_t(ny) * cw_ + nx;
      if (settled_[j] || blocked_[j]) continue;
      const float step = (k < 4 ? res : res * 1.41421356f) * 0.5f * (mi + mult_[j]);
      if (d + step < dist_[j]) {
        dist_[j] = d + step;
        open_.push({dist_[j], std::uint32_t(j)});
      }
    }
  }
  // Between cell centres; with downsampling, less the half-diagonal of a coarse cell so it stays a
  // lower bound for any point of the cell.
  if (!settled_[target]) return std::numeric_limits<double>::infinity();
  if (factor_ == 1) return double(dist_[target]);
  return std::max(0.0, double(dist_[target]) - 0.7072 * coarse_res_m_);
}

}  // namespace fieldlidar::planning
