#include "fieldlidar/people/static_background.hpp"

#include <algorithm>
#include <cmath>

namespace fieldlidar::people {

StaticBackground::StaticBackground(const StaticBackgroundConfig& c) : config_(c) {
  side_ = std::max(1, int(std::ceil(2 * c.half_extent_m / c.cell_m)));
  slots_.assign(std::size_t(side_) * std::size_t(side_), Slot{});
  decay_.resize(256);
  for (std::size_t a = 0; a < decay_.size(); ++a)
    decay_[a] = std::pow(1.0 - config_.rate, double(a));
}

double StaticBackground::decay(std::uint32_t age) const {
  return age < decay_.size() ? decay_[age] : std::pow(1.0 - config_.rate, double(age));
}

StaticBackground::Cell StaticBackground::cell_of(const Eigen::Vector2d& p) const {
  return {int(std::floor(p.x() / config_.cell_m)), int(std::floor(p.y() / config_.cell_m))};
}

std::size_t StaticBackground::slot(const Cell& c) const {
  // The grid wraps around: a cell shares its slot with the cells 2 * half_extent_m away, and
  // the slot remembers which of them it holds.
  const auto wrap = [&](int i) {
    const int r = i % side_;
    return std::size_t(r < 0 ? r + side_ : r);
  };
  return wrap(c[1]) * std::size_t(side_) + wrap(c[0]);
}

double StaticBackground::value(const Cell& c) const {
  const Slot& s = slots_[slot(c)];
  if (!holds(s, c)) return 0.0;
  return double(s.occupancy) * decay(std::uint32_t(scans_) - s.stamp);
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
    Slot& s = slots_[slot(c)];
    if (holds(s, c) && s.stamp == std::uint32_t(scans_)) continue;
    const double before = value(c);
    s.key = c;
    s.occupancy = float(before + weight * config_.rate);
    s.stamp = std::uint32_t(scans_);
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
