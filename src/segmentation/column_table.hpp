#pragma once
// (ix, iy) -> column id for the voxel-cell search of the Euclidean clustering. Internal to
// segmentation/.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace fieldlidar::segmentation::detail {

// (ix, iy) -> column id: a dense table over the cells the points span near the origin (the
// sensor, where most returns are; at most +-28 m at the default 0.5 m tolerance), open addressing
// beyond it (allocated when the first column beyond it turns up).
class ColumnTable {
 public:
  /// Points span cells [ix0, ix1] x [iy0, iy1]; `expected` columns at most.
  ColumnTable(std::int32_t ix0, std::int32_t ix1, std::int32_t iy0, std::int32_t iy1,
              std::size_t expected)
      : x0_(std::max(ix0, -kHalf)),
        y0_(std::max(iy0, -kHalf)),
        w_(std::uint32_t(std::max(0, std::min(ix1, kHalf - 1) - x0_ + 1))),
        h_(std::uint32_t(std::max(0, std::min(iy1, kHalf - 1) - y0_ + 1))),
        dense_(std::size_t(w_) * h_, -1),
        expected_(expected) {}
  std::int32_t insert(std::int32_t ix, std::int32_t iy, std::int32_t next_id) {
    const auto dx = std::uint32_t(ix - x0_), dy = std::uint32_t(iy - y0_);
    if (dx < w_ && dy < h_) {
      std::int32_t& v = dense_[std::size_t(dx) * h_ + dy];
      if (v < 0) v = next_id;
      return v;
    }
    if (values_.empty()) allocate_hash();
    const std::uint64_t k = key(ix, iy);
    for (std::size_t h = hash(k);; h = (h + 1) & mask_) {
      if (values_[h] < 0) {
        keys_[h] = k;
        values_[h] = next_id;
        return next_id;
      }
      if (keys_[h] == k) return values_[h];
    }
  }

 private:
  static constexpr std::int32_t kHalf = 96;
  static std::uint64_t key(std::int32_t ix, std::int32_t iy) {
    return (std::uint64_t(std::uint32_t(ix)) << 32) | std::uint32_t(iy);
  }
  // Room for one column per point: the table never fills.
  void allocate_hash() {
    std::size_t cap = 64;
    while (cap < expected_ * 2) cap <<= 1;
    keys_.assign(cap, 0);
    values_.assign(cap, -1);
    mask_ = cap - 1;
    while ((std::size_t(1) << bits_) < cap) ++bits_;
  }
  // Fibonacci hashing: the top bits of the product depend on every bit of ix and iy (middle bits
  // would see little of ix, which sits in the high word, and neighbouring columns would collide).
  std::size_t hash(std::uint64_t k) const {
    return std::size_t((k * 0x9E3779B97F4A7C15ull) >> (64 - bits_));
  }
  std::int32_t x0_, y0_;
  std::uint32_t w_, h_;
  std::vector<std::int32_t> dense_;
  std::size_t expected_ = 0;
  std::vector<std::uint64_t> keys_;
  std::vector<std::int32_t> values_;
  std::size_t mask_ = 0;
  int bits_ = 0;
};

}  // namespace fieldlidar::segmentation::detail
