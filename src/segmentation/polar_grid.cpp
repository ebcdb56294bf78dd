#include "polar_grid.hpp"

#if defined(__SSE2__)
#include <emmintrin.h>
#elif defined(__aarch64__)
#include <arm_neon.h>
#endif

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
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
  float narrowest = edges_.back();
  for (std::size_t k = 0; k + 1 < edges_.size(); ++k)
    narrowest = std::min(narrowest, edges_[k + 1] - edges_[k]);
  lut_scale_ = 2.f / narrowest;
  constexpr float kMaxLut = float(1 << 20);  // entries (2 MB)
  if (edges_.back() * lut_scale_ > kMaxLut) {
    lut_scale_ = kMaxLut / edges_.back();
    coarse_lut_ = true;
  }
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

namespace {

/// v[j] = sqrt(v[j]), four at a time where the instruction set has it (the same correctly
/// rounded square roots; std::sqrt in a loop stays scalar while it may have to set errno).
void square_roots(float* v, std::size_t m) {
  std::size_t j = 0;
#if defined(__SSE2__)
  for (; j + 4 <= m; j += 4) _mm_storeu_ps(v + j, _mm_sqrt_ps(_mm_loadu_ps(v + j)));
#elif defined(__aarch64__)
  for (; j + 4 <= m; j += 4) vst1q_f32(v + j, vsqrtq_f32(vld1q_f32(v + j)));
#endif
  for (; j < m; ++j) v[j] = std::sqrt(v[j]);
}

}  // namespace

PolarCells PolarGrid::assign(const PointCloud& cloud) const {
  PolarCells out;
  const std::size_t n = cloud.size();
  const std::size_t cells = cell_count();
  const int nbins = bins();
  // Per input point (written for every point, so never zeroed): its cell, `cells` for none.
  const auto cell_of = std::make_unique_for_overwrite<std::uint32_t[]>(n);
  const auto azimuth_of = std::make_unique_for_overwrite<std::uint16_t[]>(n);
  const auto rho_of = std::make_unique_for_overwrite<float[]>(n);
  out.offsets.assign(cells + 1, 0);
  std::uint32_t* const count = out.offsets.data() + 1;
  // Pass 1 in blocks, one short loop per step: coordinates, azimuth codes (SIMD), ranges, bins,
  // then the cells.
  constexpr std::size_t kBlock = 256;
  float xs[kBlock], ys[kBlock], rs[kBlock];
  std::uint16_t az[kBlock];
  std::int32_t bin[kBlock];
  std::uint32_t run_cell = 0, run = 0;
  const float r_end = edges_.back();
  for (std::size_t base = 0; base < n; base += kBlock) {
    const std::size_t m = std::min(kBlock, n - base);
    const Point* pts = cloud.points.data() + base;
    for (std::size_t j = 0; j < m; ++j) {
      xs[j] = pts[j].x;
      ys[j] = pts[j].y;
    }
    for (std::size_t j = 0; j < m; ++j) az[j] = azimuth_code(xs[j], ys[j]);  // SIMD
    for (std::size_t j = 0; j < m; ++j) rs[j] = xs[j] * xs[j] + ys[j] * ys[j];
    square_roots(rs, m);
    if (coarse_lut_)
      for (std::size_t j = 0; j < m; ++j) bin[j] = valid_point(pts[j]) ? bin_of(rs[j]) : -1;
    else
      for (std::size_t j = 0; j < m; ++j)
        bin[j] = valid_point(pts[j]) && rs[j] < r_end ? lut_bin(rs[j]) : -1;
    for (std::size_t j = 0; j < m; ++j) {
      azimuth_of[base + j] = az[j];
      rho_of[base + j] = rs[j];
      if (bin[j] < 0) {
        cell_of[base + j] = std::uint32_t(cells);
        continue;
      }
      const auto c = std::uint32_t(std::size_t(sector_of_azimuth(az[j])) * nbins + bin[j]);
      cell_of[base + j] = c;
      // Runs of points share a cell (a ring sweeps through it): counted in a register, as an
      // increment in memory per point would chain each point to the previous one's store.
      if (c != run_cell) {
        count[run_cell] += run;
        run_cell = c;
        run = 0;
      }
      ++run;
    }
  }
  count[run_cell] += run;
  for (std::size_t c = 0; c < cells; ++c) out.offsets[c + 1] += out.offsets[c];
  const std::size_t total = out.offsets.back();
  // Pass 2: the points sorted by cell (a stable counting sort: input order within a cell), with
  // each cell's lowest return (the first of equals). A run of points in one cell keeps its write
  // position and low point in registers, as in pass 1.
  out.order.resize(total);
  out.xyz.resize(total);
  out.azimuth.resize(total);
  out.ring.resize(total);
  out.rho.resize(total);
  out.lowest.assign(cells, 0);
  std::vector<std::uint32_t> fill(out.offsets.begin(), out.offsets.end() - 1);
  std::vector<float> low_z(cells, std::numeric_limits<float>::infinity());
  std::uint32_t cur = 0, k = fill[0], low_k = 0;
  float low = low_z[0];
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t c = cell_of[i];
    if (c == cells) continue;
    if (c != cur) {
      fill[cur] = k;
      low_z[cur] = low;
      out.lowest[cur] = low_k;
      cur = c;
      k = fill[c];
      low = low_z[c];
      low_k = out.lowest[c];
    }
    const Point& p = cloud.points[i];
    // A new low point without a branch (heights along a ring go up and down at random).
    const bool lower = p.z < low;
    low = lower ? p.z : low;
    low_k = lower ? k : low_k;
    out.order[k] = std::uint32_t(i);
    out.xyz[k] = {p.x, p.y, p.z};
    out.azimuth[k] = azimuth_of[i];
    out.ring[k] = p.ring;
    out.rho[k] = rho_of[i];
    ++k;
  }
  out.lowest[cur] = low_k;
  return out;
}

}  // namespace fieldlidar::segmentation
