#pragma once
// A polar grid around the sensor in the x-y plane: radial bins that lengthen with range (the
// returns thin out) and equal azimuth sectors. Internal to segmentation/.

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "fieldlidar/core/point_cloud.hpp"

namespace fieldlidar::segmentation {

/// Point::is_valid, inlined for the per-point loops and tested on the bits without a branch:
/// finite = exponent not all ones, and not the all-zero no-return (either sign of zero).
inline bool valid_point(const Point& p) {
  const std::uint32_t bx = std::bit_cast<std::uint32_t>(p.x) & 0x7fffffffu,
                      by = std::bit_cast<std::uint32_t>(p.y) & 0x7fffffffu,
                      bz = std::bit_cast<std::uint32_t>(p.z) & 0x7fffffffu;
  return (bx < 0x7f800000u) & (by < 0x7f800000u) & (bz < 0x7f800000u) & ((bx | by | bz) != 0);
}

/// a where c holds, else b, by bit masks: with FP exceptions observable (-ftrapping-math) a
/// compiler keeps ?: on floats as branches, and loops over points would not become SIMD.
inline float pick(bool c, float a, float b) {
  const std::uint32_t m = 0u - std::uint32_t(c);
  return std::bit_cast<float>((m & std::bit_cast<std::uint32_t>(a)) |
                              (~m & std::bit_cast<std::uint32_t>(b)));
}

/// atan2 accurate to ~1e-5 rad, several times faster than std::atan2; result in (-pi, pi], 0 for
/// x = y = 0. Without branches, so that a loop over points evaluates several per instruction.
inline float fast_atan2(float y, float x) {
  // Octant reduction + odd minimax polynomial on [0, 1].
  const float ax = std::abs(x), ay = std::abs(y);
  const float mx = std::max(ay, ax), mn = std::min(ay, ax);
  const float a = mn / pick(mx == 0.f, 1.f, mx);  // 0 / 1 for x = y = 0
  const float s = a * a;
  float r = ((-0.0464964749f * s + 0.15931422f) * s - 0.327622764f) * s * a + a;
  r = pick(ay > ax, 1.57079637f - r, r);
  r = pick(x < 0.f, 3.14159274f - r, r);
  return pick(y < 0.f, -r, r);
}

/// Coordinates of one point (m), copied contiguously so that the passes over a cell stream.
struct CellPoint {
  float x, y, z;
};

/// Points sorted by cell (counting sort): members(c) are the indices of cell c, points(c) their
/// coordinates in the same order.
struct PolarCells {
  std::vector<std::uint32_t> offsets;  ///< cell_count + 1
  std::vector<std::uint32_t> order;    ///< point indices grouped by cell
  std::vector<CellPoint> xyz;          ///< coordinates in `order`
  /// Azimuth of each point in `order`, atan2(y, x) + pi in 1/65536 turns (0 = -x axis).
  std::vector<std::uint16_t> azimuth;
  std::vector<std::uint16_t> ring;  ///< Point::ring of each point in `order`
  std::vector<float> rho;           ///< m, horizontal range of each point in `order`
  /// Per cell, the position in `order` of its lowest return (the first of equals); 0 if empty.
  std::vector<std::uint32_t> lowest;
  std::span<const std::uint32_t> members(std::size_t c) const {
    return {order.data() + offsets[c], order.data() + offsets[c + 1]};
  }
  std::span<const CellPoint> points(std::size_t c) const {
    return {xyz.data() + offsets[c], xyz.data() + offsets[c + 1]};
  }
};

class PolarGrid {
 public:
  /// Radial bin k spans [e_k, e_k+1) with e_k+1 = e_k + max(min_cell_m, growth * e_k).
  PolarGrid(double min_cell_m, double growth, double max_range_m, double sector_deg);

  int bins() const { return int(edges_.size()) - 1; }
  int sectors() const { return sectors_; }
  std::size_t cell_count() const { return std::size_t(bins()) * sectors_; }
  std::size_t cell(int bin, int sector) const { return std::size_t(sector) * bins() + bin; }
  float bin_centre_m(int bin) const { return 0.5f * (edges_[bin] + edges_[bin + 1]); }
  float sector_centre_rad(int sector) const;
  /// Bin of horizontal range r_m, -1 beyond the last edge.
  int bin_of(float r_m) const {
    if (!(r_m < edges_.back())) return -1;
    int b = lut_bin(r_m);
    if (coarse_lut_) {  // a range so long that the table has a coarser step
      while (b > 0 && r_m < edges_[b]) --b;
      while (b + 1 < bins() && r_m >= edges_[b + 1]) ++b;
    }
    return b;
  }
  /// Sector of a direction (x, y) (need not be normalised).
  int sector_of(float x, float y) const { return sector_of_azimuth(azimuth_code(x, y)); }
  /// atan2(y, x) + pi in 1/65536 turns.
  static std::uint16_t azimuth_code(float x, float y) {
    const float a = (fast_atan2(y, x) + 3.14159265f) * (65536.f / 6.28318531f);
    return std::uint16_t(std::int32_t(std::min(std::max(a, 0.f), 65535.f)));
  }
  int sector_of_azimuth(std::uint16_t code) const {
    return int((std::uint32_t(code) * std::uint32_t(sectors_)) >> 16);
  }
  /// Valid points within range, sorted by cell.
  PolarCells assign(const PointCloud& cloud) const;

 private:
  /// The table's step is half the narrowest bin, so at most one edge lies between its entry and
  /// r_m (either side, with the rounding of r_m * lut_scale_): one step either way, both edges
  /// loaded at once and without a branch (bins of neighbouring points alternate unpredictably).
  /// Exact for 0 <= r_m < edges_.back() unless coarse_lut_.
  int lut_bin(float r_m) const {
    const std::size_t b = lut_[std::size_t(std::int32_t(r_m * lut_scale_))];
    return int(b) - int(r_m < edges_[b]) + int(r_m >= edges_[b + 1]);
  }

  std::vector<float> edges_;
  std::vector<std::uint16_t> lut_;  ///< bin per lut_step_m of range
  float lut_scale_ = 10.f;          ///< 1 / lut step (m^-1), two steps per narrowest bin
  bool coarse_lut_ = false;         ///< the step had to be longer (table capped)
  int sectors_ = 128;
};

}  // namespace fieldlidar::segmentation
