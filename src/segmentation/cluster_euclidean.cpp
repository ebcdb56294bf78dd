// seed 002, step c: Euclidean clustering of the non-ground points.
//
// Both searches compute the same relation as pcl::EuclideanClusterExtraction over a FLANN k-d
// tree: points i and j are linked when (xi-xj)^2 + (yi-yj)^2 + (zi-zj)^2, evaluated in float in
// that order, is below float(tolerance^2); the clusters are the connected components, kept when
// their size is within [min_points, max_points].

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include <nanoflann.hpp>

#include <string>
#include "fieldlidar/core/error.hpp"

#include "cluster_common.hpp"
#include "fieldlidar/segmentation/clustering.hpp"
#include "polar_grid.hpp"

namespace fieldlidar::segmentation {
namespace {

using Xyz = ClusterPoint;

inline float squared_distance(const Xyz& a, const Xyz& b) {
  const float dx = a.x - b.x, dy = a.y - b.y, dz = a.z - b.z;
  return dx * dx + dy * dy + dz * dz;
}

/// Axis-aligned bounds of points (m).
struct Box {
  Xyz lo, hi;
  void add(const Xyz& p) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  static float gap(float lo_a, float hi_a, float lo_b, float hi_b) {
    return std::max({lo_b - hi_a, lo_a - hi_b, 0.f});
  }
  /// Squared distance between the boxes: no pair of their points is nearer.
  float gap2(const Box& o) const {
    const float dx = gap(lo.x, hi.x, o.lo.x, o.hi.x), dy = gap(lo.y, hi.y, o.lo.y, o.hi.y),
                dz = gap(lo.z, hi.z, o.lo.z, o.hi.z);
    return dx * dx + dy * dy + dz * dz;
  }
  /// Squared distance from p to the box: no point of the box is nearer to p.
  float gap2(const Xyz& p) const {
    const float dx = gap(p.x, p.x, lo.x, hi.x), dy = gap(p.y, p.y, lo.y, hi.y),
                dz = gap(p.z, p.z, lo.z, hi.z);
    return dx * dx + dy * dy + dz * dz;
  }
  /// Squared largest distance between the boxes: no pair of their points is farther apart.
  float span2(const Box& o) const {
    const float dx = std::max(hi.x - o.lo.x, o.hi.x - lo.x),
                dy = std::max(hi.y - o.lo.y, o.hi.y - lo.y),
                dz = std::max(hi.z - o.lo.z, o.hi.z - lo.z);
    return dx * dx + dy * dy + dz * dz;
  }
};

// ---- k-d tree search (nanoflann), breadth-first growth as in the seed and in PCL ----

struct ActiveCloud {
  std::vector<Xyz> pts;
  std::size_t kdtree_get_point_count() const { return pts.size(); }
  float kdtree_get_pt(std::size_t i, std::size_t dim) const {
    return dim == 0 ? pts[i].x : dim == 1 ? pts[i].y : pts[i].z;
  }
  template <class Bbox>
  bool kdtree_get_bbox(Bbox&) const {
    return false;
  }
};

using KdTree = nanoflann::KDTreeSingleIndexAdaptor<
    nanoflann::L2_Simple_Adaptor<float, ActiveCloud, float, std::uint32_t>, ActiveCloud, 3,
    std::uint32_t>;

std::vector<std::int32_t> components_kdtree(const ActiveCloud& data, float r2, std::size_t& count) {
  const std::size_t n = data.pts.size();
  std::vector<std::int32_t> comp(n, -1);
  count = 0;
  if (n == 0) return comp;
  KdTree tree(3, data, nanoflann::KDTreeSingleIndexAdaptorParams(10));
  tree.buildIndex();
  const nanoflann::SearchParams params(32, 0.f, false);
  std::vector<std::pair<std::uint32_t, float>> matches;
  std::vector<std::uint32_t> queue;
  for (std::size_t seed = 0; seed < n; ++seed) {
    if (comp[seed] >= 0) continue;
    const auto id = std::int32_t(count++);
    comp[seed] = id;
    queue.assign(1, std::uint32_t(seed));
    for (std::size_t q = 0; q < queue.size(); ++q) {
      const Xyz& p = data.pts[queue[q]];
      const float query[3] = {p.x, p.y, p.z};
      matches.clear();
      tree.radiusSearch(query, r2, matches, params);
      for (const auto& m : matches)
        if (comp[m.first] < 0) {
          comp[m.first] = id;
          queue.push_back(m.first);
        }
    }
  }
  return comp;
}

// ---- voxel-cell search: cells of side tolerance/sqrt(3) (all points of a cell are linked),
// union-find over cells, neighbouring cells (offsets up to +-2) linked by their first close pair.

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

// Scratch arrays sized for every input point and written before they are read (no zeroing).
template <class T>
std::unique_ptr<T[]> scratch(std::size_t n) {
  return std::make_unique_for_overwrite<T[]>(n);
}

/// The points taking part: input index (ascending) and coordinates.
struct Active {
  std::unique_ptr<std::uint32_t[]> index;
  std::unique_ptr<ClusterPoint[]> xyz;
  std::size_t size = 0;
};

/// The points taking part (not skipped, valid), in ascending order. Skipped points (the ground)
/// come in runs along a ring, so a branch skips them without reading them; validity is tested
/// without one (valid_point).
Active gather(const PointCloud& cloud, std::span<const std::uint8_t> skip) {
  Active a;
  a.index = scratch<std::uint32_t>(cloud.size());
  std::size_t n = 0;
  const bool all = skip.empty();
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (!all && skip[i] != 0) continue;  // ground comes in runs along a ring: predictable
    const Point& p = cloud.points[i];
    a.index[n] = std::uint32_t(i);
    n += std::size_t(valid_point(p));
  }
  // Coordinates of the points taking part only (a second pass writes a third of the bytes).
  a.size = n;
  a.xyz = scratch<ClusterPoint>(n);
  for (std::size_t k = 0; k < n; ++k) {
    const Point& p = cloud.points[a.index[k]];
    a.xyz[k] = {p.x, p.y, p.z};
  }
  return a;
}

// Labels the points (components numbered in order of their first point); nullopt when a cell
// index would leave the int32 range (coordinates beyond some 3e8 m), where the caller falls back
// to the k-d tree.
std::optional<std::vector<std::int32_t>> components_grid(const Active& active, double tolerance,
                                                         float r2, std::size_t& count) {
  count = 0;
  // The cell diagonal stays below the tolerance with margin for float rounding of coordinates.
  const double side = tolerance / std::sqrt(3.0) * (1.0 - 1e-4);
  const double inv = 1.0 / side;
  const std::size_t n = active.size;
  auto col_of = scratch<std::uint32_t>(n);
  auto iz_of = scratch<std::int32_t>(n);
  std::vector<std::int32_t> cix, ciy, col_zlo, col_zhi;  // per column id: ix, iy, iz range
  std::vector<std::uint32_t> col_count;
  bool far = false;  // a cell index beyond +-2^30 (some 3e8 m at 0.5 m)
  const auto cell_index = [&](float v) {
    const double c = double(v) * inv;
    far |= !(std::abs(c) < 1073741824.0);
    const auto t = std::int32_t(std::clamp(c, -1073741824.0, 1073741824.0));
    return t - std::int32_t(double(t) > c);  // floor
  };
  // The cells the points span (floor is monotonic: the cells of the bounds' corners).
  Box points_box{{0.f, 0.f, 0.f}, {0.f, 0.f, 0.f}};
  if (n > 0) points_box.lo = points_box.hi = active.xyz[0];
  for (std::size_t k = 1; k < n; ++k) points_box.add(active.xyz[k]);
  const Xyz &lo = points_box.lo, &hi = points_box.hi;
  // Within 512 cells of the origin (some 150 m at 0.5 m) cell indices in float are exact enough:
  // float(v * inv) is off by at most 512 * 2^-24 of a cell, which widens a cell by 6e-5 of its
  // side, inside the 1e-4 margin; and cheaper than the double path needed beyond.
  const double extent = std::max({-lo.x, -lo.y, -lo.z, hi.x, hi.y, hi.z});
  const bool near = extent * inv < 512.0;
  const auto inv_f = float(inv);
  const auto cell_index_near = [inv_f](float v) {
    const float c = v * inv_f;
    const auto t = std::int32_t(c);
    return t - std::int32_t(float(t) > c);  // floor
  };
  const auto window = [&](float v) { return near ? cell_index_near(v) : cell_index(v); };
  auto table =
      std::make_unique<ColumnTable>(window(lo.x), window(hi.x), window(lo.y), window(hi.y), n);
  // A run of points in one column (a ring sweeping over an object) keeps the column's count and
  // iz range in registers: per-point updates in memory would chain each point to the last.
  std::uint32_t run_id = 0, run_n = 0;
  std::int32_t run_lo = 0, run_hi = 0;
  const auto flush_run = [&] {
    if (run_n == 0) return;
    col_count[run_id] += run_n;
    col_zlo[run_id] = std::min(col_zlo[run_id], run_lo);
    col_zhi[run_id] = std::max(col_zhi[run_id], run_hi);
  };
  // Cell indices first, in a loop of their own (independent per point, so many in flight).
  auto cells_of = scratch<std::int32_t>(3 * n);
  if (near)
    for (std::size_t k = 0; k < 3 * n; ++k) cells_of[k] = cell_index_near((&active.xyz[0].x)[k]);
  else
    for (std::size_t k = 0; k < 3 * n; ++k) cells_of[k] = cell_index((&active.xyz[0].x)[k]);
  for (std::size_t k = 0; k < n; ++k) {
    const std::int32_t ix = cells_of[3 * k], iy = cells_of[3 * k + 1], iz = cells_of[3 * k + 2];
    const auto next = std::int32_t(cix.size());
    const auto id = std::uint32_t(table->insert(ix, iy, next));
    if (id == std::uint32_t(next)) {
      cix.push_back(ix);
      ciy.push_back(iy);
      col_count.push_back(0);
      col_zlo.push_back(iz);
      col_zhi.push_back(iz);
    }
    if (id != run_id) {
      flush_run();
      run_id = id;
      run_n = 0;
      run_lo = run_hi = iz;
    }
    ++run_n;
    run_lo = std::min(run_lo, iz);
    run_hi = std::max(run_hi, iz);
    col_of[k] = id;
    iz_of[k] = iz;
  }
  flush_run();
  table.reset();
  if (far) return std::nullopt;
  std::vector<std::int32_t> comp(n);
  if (n == 0) return comp;
  // Columns renumbered in (ix, iy) order: neighbours are then found by a merge over that order
  // (sequential reads) instead of look-ups spread over the table.
  const std::size_t ncols = cix.size();
  std::vector<std::uint32_t> rank(ncols), column_id(ncols);
  std::vector<std::int32_t> sx(ncols), sy(ncols);
  std::vector<std::uint32_t> col_start(ncols + 1, 0);
  {
    struct ColumnKey {
      std::uint64_t key;
      std::uint32_t id;
    };
    std::vector<ColumnKey> keys(ncols);
    for (std::size_t c = 0; c < ncols; ++c)
      keys[c] = {(std::uint64_t(std::uint32_t(cix[c]) ^ 0x80000000u) << 32) |
                     (std::uint32_t(ciy[c]) ^ 0x80000000u),
                 std::uint32_t(c)};
    std::sort(keys.begin(), keys.end(),
              [](const ColumnKey& a, const ColumnKey& b) { return a.key < b.key; });
    for (std::size_t r = 0; r < ncols; ++r) {
      const std::uint32_t c = keys[r].id;
      rank[c] = std::uint32_t(r);
      column_id[r] = c;
      sx[r] = cix[c];
      sy[r] = ciy[c];
      col_start[r + 1] = col_start[r] + col_count[c];
    }
  }
  // Points sorted by (column, iz, k): cells are the runs of one (column, iz). When the columns'
  // iz ranges are short (as over the ground), one counting sort over (column, iz) buckets does
  // it; else the points are sorted by column and then each column by (iz, k).
  auto item_point = scratch<std::uint32_t>(n);  // point k of each item, in that order
  std::vector<std::uint32_t> cell_start;        // into the items
  std::vector<std::int32_t> cell_iz;
  std::vector<std::uint32_t> col_cell(ncols + 1, 0);
  cell_start.reserve(n + 1);
  cell_iz.reserve(n);
  std::vector<std::uint32_t> bucket_base(ncols + 1, 0);
  std::uint64_t buckets = 0;
  for (std::size_t r = 0; r < ncols; ++r) {
    const std::uint32_t c = column_id[r];
    bucket_base[r] = std::uint32_t(std::min<std::uint64_t>(buckets, 0xffffffffu));
    buckets += std::uint64_t(std::int64_t(col_zhi[c]) - col_zlo[c] + 1);
  }
  if (buckets <= 4 * std::uint64_t(n) + 4096) {
    bucket_base[ncols] = std::uint32_t(buckets);
    // Bucket of each point (in col_of), counted in runs.
    std::vector<std::uint32_t> start(buckets + 1, 0);
    std::uint32_t run_b = 0, run_count = 0;
    for (std::size_t k = 0; k < n; ++k) {
      const std::uint32_t c = col_of[k];
      const std::uint32_t b = bucket_base[rank[c]] + std::uint32_t(iz_of[k] - col_zlo[c]);
      col_of[k] = b;
      if (b != run_b) {
        start[run_b + 1] += run_count;
        run_b = b;
        run_count = 0;
      }
      ++run_count;
    }
    start[run_b + 1] += run_count;
    for (std::size_t b = 0; b < buckets; ++b) start[b + 1] += start[b];
    // The non-empty buckets, written without a branch (empty and full ones interleave at random).
    cell_start.resize(n + 1);
    cell_iz.resize(n + 1);
    std::size_t cells = 0;
    for (std::size_t r = 0; r < ncols; ++r) {
      col_cell[r] = std::uint32_t(cells);
      const std::int32_t zlo = col_zlo[column_id[r]];
      for (std::uint32_t b = bucket_base[r]; b < bucket_base[r + 1]; ++b) {
        cell_start[cells] = start[b];
        cell_iz[cells] = zlo + std::int32_t(b - bucket_base[r]);
        cells += std::size_t(start[b + 1] > start[b]);
      }
    }
    cell_start.resize(cells);
    cell_iz.resize(cells);
    std::uint32_t cur = 0, pos = start[0];
    for (std::size_t k = 0; k < n; ++k) {
      const std::uint32_t b = col_of[k];
      if (b != cur) {
        start[cur] = pos;
        cur = b;
        pos = start[b];
      }
      item_point[pos++] = std::uint32_t(k);
    }
  } else {
    // Each keyed (iz, k) in one integer so that a column sorts with plain integer compares (iz
    // offset by 2^31 keeps the order of negative heights); filled from each column's end.
    auto items = scratch<std::uint64_t>(n);
    std::vector<std::uint32_t> end(col_start.begin() + 1, col_start.end());
    for (std::size_t k = 0; k < n; ++k)
      items[--end[rank[col_of[k]]]] =
          (std::uint64_t(std::uint32_t(iz_of[k]) ^ 0x80000000u) << 32) | k;
    const auto iz_key = [&](std::size_t item) { return std::uint32_t(items[item] >> 32); };
    for (std::size_t c = 0; c < ncols; ++c) {
      const std::uint32_t b = col_start[c], e = col_start[c + 1];
      std::sort(items.get() + b, items.get() + e);
      col_cell[c] = std::uint32_t(cell_start.size());
      for (std::uint32_t it = b; it < e; ++it)
        if (it == b || iz_key(it) != iz_key(it - 1)) {
          cell_start.push_back(it);
          cell_iz.push_back(std::int32_t(iz_key(it) ^ 0x80000000u));
        }
    }
    for (std::size_t k = 0; k < n; ++k) item_point[k] = std::uint32_t(items[k]);
  }
  const auto point_of = [&](std::size_t item) { return item_point[item]; };
  col_cell[ncols] = std::uint32_t(cell_start.size());
  const std::size_t ncells = cell_start.size();
  cell_start.push_back(std::uint32_t(n));
  // Coordinates in item order for cache-friendly pair tests, and each cell's bounds.
  auto sorted = scratch<Xyz>(n);
  for (std::size_t k = 0; k < n; ++k) sorted[k] = active.xyz[point_of(k)];
  auto bounds = scratch<Box>(ncells);
  for (std::size_t cell = 0; cell < ncells; ++cell) {
    Box& b = bounds[cell];
    b.lo = b.hi = sorted[cell_start[cell]];
    for (std::uint32_t k = cell_start[cell] + 1; k < cell_start[cell + 1]; ++k) b.add(sorted[k]);
  }
  // Bounds decide most cell pairs without a pair test: the distance between two boxes, in float
  // with the pair test's operations, bounds every pair's below (rounding is monotonic); a margin of
  // 1e-5 keeps that true should the compiler fuse the multiply-adds differently.
  const float r2_far = r2 * (1.f + 1e-5f), r2_near = r2 * (1.f - 1e-5f);
  DisjointSets sets(ncells);
  auto try_link = [&](std::uint32_t a, std::uint32_t b) {
    if (sets.find(a) == sets.find(b)) return;
    const Box &ba = bounds[a], &bb = bounds[b];
    if (ba.gap2(bb) >= r2_far) return;
    if (ba.span2(bb) < r2_near) {
      sets.unite(a, b);
      return;
    }
    for (std::uint32_t i = cell_start[a]; i < cell_start[a + 1]; ++i) {
      if (bb.gap2(sorted[i]) >= r2_far) continue;
      for (std::uint32_t j = cell_start[b]; j < cell_start[b + 1]; ++j)
        if (squared_distance(sorted[i], sorted[j]) < r2) {
          sets.unite(a, b);
          return;
        }
    }
  };
  // Cells of columns c and d (d a neighbour column) within two steps in z.
  const auto link_columns = [&](std::size_t c, std::size_t d) {
    const std::uint32_t c0 = col_cell[c], c1 = col_cell[c + 1];
    const std::uint32_t d0 = col_cell[d], d1 = col_cell[d + 1];
    std::uint32_t lo = d0;
    for (std::uint32_t a = c0; a < c1; ++a) {
      while (lo < d1 && cell_iz[lo] < cell_iz[a] - 2) ++lo;
      for (std::uint32_t b = lo; b < d1 && cell_iz[b] <= cell_iz[a] + 2; ++b) try_link(a, b);
    }
  };
  // Neighbour columns in one half-plane (the other half sees this column from its side): iy + 1
  // and iy + 2 in the same row, iy - 2 .. iy + 2 in rows ix + 1 and ix + 2. Columns are in (ix, iy)
  // order, so the first candidate of each neighbour row only moves forward.
  // Same column first: cells one or two steps apart in z. A column whose cells all end up in
  // one set is whole; between two whole columns already in one set there is nothing to test.
  std::vector<std::uint8_t> whole(ncols);
  for (std::size_t c = 0; c < ncols; ++c) {
    const std::uint32_t c0 = col_cell[c], c1 = col_cell[c + 1];
    for (std::uint32_t a = c0; a < c1; ++a)
      for (std::uint32_t b = a + 1; b < c1 && cell_iz[b] - cell_iz[a] <= 2; ++b) try_link(a, b);
    bool one = true;
    for (std::uint32_t a = c0 + 1; a < c1 && one; ++a) one = sets.find(a) == sets.find(c0);
    whole[c] = one;
  }
  const auto visit = [&](std::size_t c, std::size_t d) {
    if (whole[c] && whole[d] && sets.find(col_cell[c]) == sets.find(col_cell[d])) return;
    link_columns(c, d);
  };
  std::size_t next_row[3] = {0, 0, 0};
  for (std::size_t c = 0; c < ncols; ++c) {
    for (std::size_t d = c + 1; d < ncols && sx[d] == sx[c] && sy[d] <= sy[c] + 2; ++d) visit(c, d);
    for (int dx = 1; dx <= 2; ++dx) {
      const std::int32_t row = sx[c] + dx, first = sy[c] - 2, last = sy[c] + 2;
      std::size_t& d = next_row[dx];
      while (d < ncols && (sx[d] < row || (sx[d] == row && sy[d] < first))) ++d;
      for (std::size_t e = d; e < ncols && sx[e] == row && sy[e] <= last; ++e) visit(c, e);
    }
  }
  // Each point gets its cell's root, then the roots are numbered in order of their first point.
  for (std::uint32_t cell = 0; cell < ncells; ++cell) {
    const auto root = std::int32_t(sets.find(cell));
    for (std::uint32_t k = cell_start[cell]; k < cell_start[cell + 1]; ++k)
      comp[point_of(k)] = root;
  }
  std::vector<std::int32_t> number(ncells, -1);
  for (std::int32_t& c : comp) {
    std::int32_t& id = number[std::size_t(c)];
    if (id < 0) id = std::int32_t(count++);
    c = id;
  }
  return comp;
}

}  // namespace

ClusterResult cluster_euclidean(const PointCloud& cloud, std::span<const std::uint8_t> skip,
                                const EuclideanClusterConfig& config) {
  if (!(config.tolerance_m > 0) || !std::isfinite(config.tolerance_m))
    throw Error("euclidean clustering: tolerance_m = " + std::to_string(config.tolerance_m) +
                " must be a positive distance");
  if (!skip.empty() && skip.size() != cloud.size())
    throw Error("euclidean clustering: skip has " + std::to_string(skip.size()) +
                " entries for a cloud of " + std::to_string(cloud.size()) + " points");
  // pcl::KdTreeFLANN::radiusSearch hands FLANN static_cast<float>(radius * radius).
  const auto r2 = static_cast<float>(config.tolerance_m * config.tolerance_m);
  std::size_t count = 0;
  const Active active = gather(cloud, skip);
  std::optional<std::vector<std::int32_t>> component;
  if (config.search == EuclideanClusterConfig::Search::kGrid)
    component = components_grid(active, config.tolerance_m, r2, count);
  if (!component) {
    ActiveCloud data;
    data.pts.assign(active.xyz.get(), active.xyz.get() + active.size);
    component = components_kdtree(data, r2, count);
  }
  return make_clusters(cloud.size(), {active.index.get(), active.size},
                       {active.xyz.get(), active.size}, *component, count, config.min_points,
                       config.max_points);
}

}  // namespace fieldlidar::segmentation
