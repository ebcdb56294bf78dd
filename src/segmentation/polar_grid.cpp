#include "polar_grid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace fieldlidar::segmentation {

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

PolarCells PolarGrid::assign(const PointCloud& cloud) const {
  PolarCells out;
  const std::size_t n = cloud.size();
  std::vector<std::uint32_t> cell_of(n, std::uint32_t(-1));
  std::vector<std::uint16_t> azimuth_of(n);
  std::vector<float> rho_of(n);
  out.offsets.assign(cell_count() + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const Point& p = cloud.points[i];
    if (!valid_point(p)) continue;
    const float r = std::sqrt(p.x * p.x + p.y * p.y);
    const int b = bin_of(r);
    if (b < 0) continue;
    const std::uint16_t az = azimuth_code(p.x, p.y);
    const auto c = std::uint32_t(cell(b, sector_of_azimuth(az)));
    cell_of[i] = c;
    azimuth_of[i] = az;
    rho_of[i] = r;
    ++out.offsets[c + 1];
  }
  for (std::size_t c = 0; c < cell_count(); ++c) out.offsets[c + 1] += out.offsets[c];
  out.order.resize(out.offsets.back());
  std::vector<std::uint32_t> fill(out.offsets.begin(), out.offsets.end() - 1);
  out.xyz.resize(out.offsets.back());
  out.azimuth.resize(out.offsets.back());
  out.ring.resize(out.offsets.back());
  out.rho.resize(out.offsets.back());
  out.lowest.assign(cell_count(), 0);
  std::vector<float> low_z(cell_count(), std::numeric_limits<float>::infinity());
  for (std::size_t i = 0; i < n; ++i)
    if (cell_of[i] != std::uint32_t(-1)) {
      const std::uint32_t c = cell_of[i];
      const std::uint32_t k = fill[c]++;
      if (cloud.points[i].z < low_z[c]) {
        low_z[c] = cloud.points[i].z;
        out.lowest[c] = k;
      }
      out.order[k] = std::uint32_t(i);
      const Point& p = cloud.points[i];
      out.xyz[k] = {p.x, p.y, p.z};
      out.azimuth[k] = azimuth_of[i];
      out.ring[k] = p.ring;
      out.rho[k] = rho_of[i];
    }
  return out;
}

}  // namespace fieldlidar::segmentation
