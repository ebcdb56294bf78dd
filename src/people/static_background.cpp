#include "fieldlidar/people/static_background.hpp"

#include <algorithm>
#include <cmath>

namespace fieldlidar::people {

StaticBackground::StaticBackground(const StaticBackgroundConfig& c) : config_(c) {
  side_ = std::max(1, int(std::ceil(2 * c.half_extent_m / c.cell_m)));
  occupancy_.assign(std::size_t(side_) * std::size_t(side_), 0.f);
  stamp_.assign(occupancy_.size(), 0);
  key_.assign(occupancy_.size(), {kNoCell, kNoCell});
}

StaticBackground::Cell StaticBackground::cell_of(const Eigen::Vector2d& p) const {
  return {int(std::floor(p.x() / config_.cell_m)), int(std::floor(p.y() / config_.cell_m))};
}

std::size_t StaticBackground::slot(const Cell& c) const {
  // The grid wraps around: a cell shares its slot with the cells 2 * half_extent_m away, and
  // the slot remembers which of them it holds.
  const auto wrap = [&](int i) { return std::size_t(((i % side_) + side_) % side_); };
  return wrap(c[1]) * std::size_t(side_) + wrap(c[0]);
}

double StaticBackground::value(const Cell& c) const {
  const std::size_t i = slot(c);
  if (key_[i] != c) return 0.0;
  const auto age = std::uint32_t(scans_) - stamp_[i];
  return double(occupancy_[i]) * std::pow(1.0 - config_.rate, double(age));
}

double StaticBackground::full() const {
  // Occupancy of a cell hit in every scan since the start (1 - (1-a)^n).
  return 1.0 - std::pow(1.0 - config_.rate, double(scans_));
}

void StaticBackground::update(std::span<const Eigen::Vector2d> points) {
  ++scans_;
  add(points, 1.0);
}

void StaticBackground::add(std::span<const Eigen::Vector2d> points, double weight) {
  // Each cell decays by (1 - rate) per scan; the decay is applied lazily when a cell is touched
  // (stamp_ = the scan of its last update), and a cell counts once per scan. A slot taken by a
  // new cell (the old one lies 2 * half_extent_m away, behind the sensor) starts empty.
  for (const auto& p : points) {
    if (!p.allFinite() || std::abs(p.x()) > kMaxCoordinate_m || std::abs(p.y()) > kMaxCoordinate_m)
      continue;
    const Cell c = cell_of(p);
    const std::size_t i = slot(c);
    if (key_[i] == c && stamp_[i] == std::uint32_t(scans_)) continue;
    const double before = value(c);
    key_[i] = c;
    occupancy_[i] = float(before + weight * config_.rate);
    stamp_[i] = std::uint32_t(scans_);
  }
}

bool StaticBackground::is_static(std::span<const Eigen::Vector2d> arc) const {
  if (scans_ < config_.warmup_scans || arc.empty()) return false;
  // A grid that never learns (rate 0) holds no background.
  if (!(full() > 0)) return false;
  const double needed = config_.static_occupancy * full();
  std::size_t on_background = 0;
  for (const auto& p : arc) {
    if (!p.allFinite() || std::abs(p.x()) > kMaxCoordinate_m || std::abs(p.y()) > kMaxCoordinate_m)
      continue;
    const Cell c = cell_of(p);
    double best = 0;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) best = std::max(best, value({c[0] + dx, c[1] + dy}));
    if (best >= needed) ++on_background;
  }
  return double(on_background) >= config_.static_fraction * double(arc.size());
}

}  // namespace fieldlidar::people
