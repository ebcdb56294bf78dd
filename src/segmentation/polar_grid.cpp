#include "polar_grid.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace fieldlidar::segmentation {

float fast_atan2(float y, float x) {
  // Octant reduction + odd minimax polynomial on [0, 1].
  const float ax = std::abs(x), ay = std::abs(y);
  const float mx = std::max(ax, ay), mn = std::min(ax, ay);
  if (mx == 0.f) return 0.f;
  const float a = mn / mx;
  const float s = a * a;
  float r = ((-0.0464964749f * s + 0.15931422f) * s - 0.327622764f) * s * a + a;
  if (ay > ax) r = 1.57079637f - r;
  if (x < 0.f) r = 3.14159274f - r;
  if (y < 0.f) r = -r;
  return r;
}

PolarGrid::PolarGrid(double min_cell_m, double growth, double max_range_m, double sector_deg) {
  min_cell_m = std::max(min_cell_m, 0.05);
  double e = 0.0;
  edges_.push_back(0.f);
  while (e < max_range_m) {
    e += std::max(min_cell_m, growth * e);
    edges_.push_back(float(e));
  }
  lut_scale_ = 10.f;
  lut_.resize(std::size_t(edges_.back() * lut_scale_) + 2);
  int b = 0;
  for (std::size_t k = 0; k < lut_.size(); ++k) {
    const float r = float(k) / lut_scale_;
    while (b + 1 < int(edges_.size()) - 1 && r >= edges_[b + 1]) ++b;
    lut_[k] = std::uint16_t(b);
  }
  sectors_ = std::max(1, int(std::lround(360.0 / std::max(sector_deg, 0.1))));
}

float PolarGrid::sector_centre_rad(int sector) const {
  return float(-std::numbers::pi + (sector + 0.5) * 2.0 * std::numbers::pi / sectors_);
}

int PolarGrid::bin_of(float r_m) const {
  if (!(r_m < edges_.back())) return -1;
  int b = lut_[std::size_t(r_m * lut_scale_)];
  // The table has a 0.1 m step; step to the exact bin.
  while (b > 0 && r_m < edges_[b]) --b;
  while (b + 1 < bins() && r_m >= edges_[b + 1]) ++b;
  return b;
}

int PolarGrid::sector_of(float x, float y) const {
  const float a = fast_atan2(y, x) + 3.14159265f;
  int s = int(a * (float(sectors_) / 6.28318531f));
  return std::clamp(s, 0, sectors_ - 1);
}

PolarCells PolarGrid::assign(const PointCloud& cloud) const {
  PolarCells out;
  const std::size_t n = cloud.size();
  std::vector<std::uint32_t> cell_of(n, std::uint32_t(-1));
  out.offsets.assign(cell_count() + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const Point& p = cloud.points[i];
    if (!p.is_valid()) continue;
    const float r = std::sqrt(p.x * p.x + p.y * p.y);
    const int b = bin_of(r);
    if (b < 0) continue;
    const auto c = std::uint32_t(cell(b, sector_of(p.x, p.y)));
    cell_of[i] = c;
    ++out.offsets[c + 1];
  }
  for (std::size_t c = 0; c < cell_count(); ++c) out.offsets[c + 1] += out.offsets[c];
  out.order.resize(out.offsets.back());
  std::vector<std::uint32_t> fill(out.offsets.begin(), out.offsets.end() - 1);
  for (std::size_t i = 0; i < n; ++i)
    if (cell_of[i] != std::uint32_t(-1)) out.order[fill[cell_of[i]]++] = std::uint32_t(i);
  return out;
}

}  // namespace fieldlidar::segmentation
