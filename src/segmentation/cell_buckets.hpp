#pragma once
// Points bucketed by square 2D cell, for the neighbourhood queries of the undergrowth test.
// Internal to segmentation/.

#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "polar_grid.hpp"

namespace fieldlidar::segmentation::detail {

// Points bucketed by square 2D cell through a hash of the cell's indices: one counting sort
// into the hash's slots, so that the points of a slot are contiguous. Two cells sharing a slot
// only cost the queries a few more tests.
class CellBuckets {
 public:
  CellBuckets(float cell_m, std::span<const CellPoint> pts) : inv_(1.f / cell_m) {
    std::size_t size = 64;
    while (size < pts.size()) size *= 2;
    mask_ = std::uint32_t(size - 1);
    start_.assign(size + 1, 0);
    std::vector<std::uint32_t> slots(pts.size());
    for (std::size_t k = 0; k < pts.size(); ++k) {
      slots[k] = slot_of(cell(pts[k].x), cell(pts[k].y));
      ++start_[slots[k] + 1];
    }
    for (std::size_t k = 0; k < size; ++k) start_[k + 1] += start_[k];
    pts_.resize(pts.size());
    std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
    for (std::size_t k = 0; k < pts.size(); ++k) pts_[fill[slots[k]]++] = pts[k];
  }
  int cell(float v) const { return int(std::floor(v * inv_)); }
  /// Calls f(q) for the points q of the 3 x 3 cells around cell (ix, iy), and some others,
  /// until f returns false.
  template <class F>
  void around(int ix, int iy, F&& f) const {
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy) {
        const std::uint32_t slot = slot_of(ix + dx, iy + dy);
        for (std::uint32_t k = start_[slot]; k < start_[slot + 1]; ++k)
          if (!f(pts_[k])) return;
      }
  }

 private:
  std::uint32_t slot_of(int ix, int iy) const {
    return ((std::uint32_t(ix) * 73856093u) ^ (std::uint32_t(iy) * 19349663u)) & mask_;
  }
  float inv_;
  std::uint32_t mask_ = 0;
  std::vector<std::uint32_t> start_;
  std::vector<CellPoint> pts_;
};

}  // namespace fieldlidar::segmentation::detail
