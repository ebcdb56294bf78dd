#pragma once
// A polar grid around the sensor in the x-y plane: radial bins that lengthen with range (the
// returns thin out) and equal azimuth sectors. Internal to segmentation/.

#include <cstdint>
#include <span>
#include <vector>

#include "fieldlidar/core/point_cloud.hpp"

namespace fieldlidar::segmentation {

/// Points sorted by cell (counting sort): members(c) are the indices of cell c.
struct PolarCells {
  std::vector<std::uint32_t> offsets;  ///< cell_count + 1
  std::vector<std::uint32_t> order;    ///< point indices grouped by cell
  std::span<const std::uint32_t> members(std::size_t c) const {
    return {order.data() + offsets[c], order.data() + offsets[c + 1]};
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
  int bin_of(float r_m) const;
  /// Sector of a direction (x, y) (need not be normalised).
  int sector_of(float x, float y) const;
  /// Valid points within range, sorted by cell.
  PolarCells assign(const PointCloud& cloud) const;

 private:
  std::vector<float> edges_;
  std::vector<std::uint16_t> lut_;  ///< bin per lut_step_m of range
  float lut_scale_ = 10.f;          ///< 1 / lut step (m^-1)
  int sectors_ = 128;
};

/// atan2 accurate to ~1e-5 rad, several times faster than std::atan2; result in (-pi, pi].
float fast_atan2(float y, float x);

}  // namespace fieldlidar::segmentation
