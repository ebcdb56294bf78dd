#include "fieldlidar/people/static_background.hpp"

#include <algorithm>
#include <cmath>

namespace fieldlidar::people {

StaticBackground::StaticBackground(const StaticBackgroundConfig& c) : config_(c) {
  side_ = std::max(1, int(std::ceil(2 * c.half_extent_m / c.cell_m)));
  occupancy_.assign(std::size_t(side_) * std::size_t(side_), 0.f);
  stamp_.assign(occupancy_.size(), 0);
}

int StaticBackground::index(const Eigen::Vector2d& p) const {
  const int ix = int(std::floor((p.x() + config_.half_extent_m) / config_.cell_m));
  const int iy = int(std::floor((p.y() + config_.half_extent_m) / config_.cell_m));
  if (ix < 0 || iy < 0 || ix >= side_ || iy >= side_) return -1;
  return iy * side_ + ix;
}

double StaticBackground::value(int i) const {
  const auto age = std::uint32_t(scans_) - stamp_[std::size_t(i)];
  return double(occupancy_[std::size_t(i)]) * std::pow(1.0 - config_.rate, double(age));
}

void StaticBackground::update(std::span<const Eigen::Vector2d> points) {
  ++scans_;
  // Each cell decays by (1 - rate) per scan; the decay is applied lazily when a cell is touched
  // (stamp_ = the scan of its last update), and a cell counts once per scan.
  for (const auto& p : points) {
    const int i = p.allFinite() ? index(p) : -1;
    if (i < 0 || stamp_[std::size_t(i)] == std::uint32_t(scans_)) continue;
    occupancy_[std::size_t(i)] = float(value(i) + config_.rate);
    stamp_[std::size_t(i)] = std::uint32_t(scans_);
  }
}

bool StaticBackground::is_static(std::span<const Eigen::Vector2d> arc) const {
  if (scans_ < config_.warmup_scans || arc.empty()) return false;
  // Occupancy relative to a cell hit in every scan since the start (1 - (1-a)^n).
  const double full = 1.0 - std::pow(1.0 - config_.rate, double(scans_));
  std::size_t on_background = 0;
  for (const auto& p : arc) {
    const int i = index(p);
    if (i < 0) continue;
    const int ix = i % side_, iy = i / side_;
    double best = 0;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int x = ix + dx, y = iy + dy;
        if (x >= 0 && y >= 0 && x < side_ && y < side_) best = std::max(best, value(y * side_ + x));
      }
    if (best / full >= config_.static_occupancy) ++on_background;
  }
  return double(on_background) >= config_.static_fraction * double(arc.size());
}

}  // namespace fieldlidar::people
