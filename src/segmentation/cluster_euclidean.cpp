// seed 002, step c: Euclidean clustering of the non-ground points.
//
// Both searches compute the same relation as pcl::EuclideanClusterExtraction over a FLANN k-d
// tree: points i and j are linked when (xi-xj)^2 + (yi-yj)^2 + (zi-zj)^2, evaluated in float in
// that order, is below float(tolerance^2); the clusters are the connected components, kept when
// their size is within [min_points, max_points].

#include <algorithm>
#include <cmath>
#include <vector>

#include <nanoflann.hpp>

#include <string>
#include "fieldlidar/core/error.hpp"

#include "cluster_common.hpp"
#include "fieldlidar/segmentation/clustering.hpp"
#include "polar_grid.hpp"

namespace fieldlidar::segmentation {
namespace {

struct Xyz {
  float x, y, z;
};

inline float squared_distance(const Xyz& a, const Xyz& b) {
  const float dx = a.x - b.x, dy = a.y - b.y, dz = a.z - b.z;
  return dx * dx + dy * dy + dz * dz;
}

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

// (ix, iy) -> column id: a dense table near the origin (the sensor, where most returns are),
// open addressing beyond it.
class ColumnTable {
 public:
  explicit ColumnTable(std::size_t expected) : dense_(std::size_t(kSide) * kSide, -1) {
    std::size_t cap = 64;
    while (cap < expected * 2) cap <<= 1;
    keys_.assign(cap, 0);
    values_.assign(cap, -1);
    mask_ = cap - 1;
    while ((std::size_t(1) << bits_) < cap) ++bits_;
  }
  std::int32_t find(std::int32_t ix, std::int32_t iy) const {
    if (in_dense(ix, iy)) return dense_[dense_index(ix, iy)];
    const std::uint64_t k = key(ix, iy);
    for (std::size_t h = hash(k);; h = (h + 1) & mask_) {
      if (values_[h] < 0) return -1;
      if (keys_[h] == k) return values_[h];
    }
  }
  std::int32_t insert(std::int32_t ix, std::int32_t iy, std::int32_t next_id) {
    if (in_dense(ix, iy)) {
      std::int32_t& v = dense_[dense_index(ix, iy)];
      if (v < 0) v = next_id;
      return v;
    }
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
  static constexpr std::int32_t kHalf = 96;  // cells: +-28 m at the default 0.5 m tolerance
  static constexpr std::int32_t kSide = 2 * kHalf;
  static bool in_dense(std::int32_t ix, std::int32_t iy) {
    return std::uint32_t(ix + kHalf) < std::uint32_t(kSide) &&
           std::uint32_t(iy + kHalf) < std::uint32_t(kSide);
  }
  static std::size_t dense_index(std::int32_t ix, std::int32_t iy) {
    return std::size_t(ix + kHalf) * kSide + std::size_t(iy + kHalf);
  }
  static std::uint64_t key(std::int32_t ix, std::int32_t iy) {
    return (std::uint64_t(std::uint32_t(ix)) << 32) | std::uint32_t(iy);
  }
  // Fibonacci hashing: the top bits of the product depend on every bit of ix and iy (middle bits
  // would see little of ix, which sits in the high word, and neighbouring columns would collide).
  std::size_t hash(std::uint64_t k) const {
    return std::size_t((k * 0x9E3779B97F4A7C15ull) >> (64 - bits_));
  }
  std::vector<std::int32_t> dense_;
  std::vector<std::uint64_t> keys_;
  std::vector<std::int32_t> values_;
  std::size_t mask_ = 0;
  int bits_ = 0;
};

std::vector<std::int32_t> components_grid(const ActiveCloud& data, double tolerance, float r2,
                                          std::size_t& count) {
  const std::size_t n = data.pts.size();
  count = 0;
  std::vector<std::int32_t> comp(n, -1);
  if (n == 0) return comp;
  // The cell diagonal stays below the tolerance with margin for float rounding of coordinates.
  const double side = tolerance / std::sqrt(3.0) * (1.0 - 1e-4);
  const double inv = 1.0 / side;
  struct Item {
    std::int32_t iz;
    std::uint32_t idx;
  };
  std::vector<std::int32_t> col_of(n);
  std::vector<std::int32_t> cix, ciy;
  ColumnTable table(n);  // at most one column per point
  std::vector<std::uint32_t> col_count;
  std::vector<std::int32_t> iz_of(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Xyz& p = data.pts[i];
    const auto ix = std::int32_t(std::floor(double(p.x) * inv));
    const auto iy = std::int32_t(std::floor(double(p.y) * inv));
    iz_of[i] = std::int32_t(std::floor(double(p.z) * inv));
    const std::int32_t id = table.insert(ix, iy, std::int32_t(cix.size()));
    if (id == std::int32_t(cix.size())) {
      cix.push_back(ix);
      ciy.push_back(iy);
      col_count.push_back(0);
    }
    col_of[i] = id;
    ++col_count[id];
  }
  const std::size_t ncols = cix.size();
  std::vector<std::uint32_t> col_start(ncols + 1, 0);
  for (std::size_t c = 0; c < ncols; ++c) col_start[c + 1] = col_start[c] + col_count[c];
  std::vector<Item> items(n);
  {
    std::vector<std::uint32_t> fill(col_start.begin(), col_start.end() - 1);
    for (std::size_t i = 0; i < n; ++i) items[fill[col_of[i]]++] = {iz_of[i], std::uint32_t(i)};
  }
  // Cells: runs of equal iz within a column (items sorted by iz per column).
  std::vector<std::uint32_t> cell_start;  // into items
  std::vector<std::int32_t> cell_iz;
  std::vector<std::uint32_t> col_cell(ncols + 1, 0);
  cell_start.reserve(n / 2 + 1);
  for (std::size_t c = 0; c < ncols; ++c) {
    auto b = items.begin() + col_start[c], e = items.begin() + col_start[c + 1];
    std::sort(b, e, [](const Item& u, const Item& v) { return u.iz < v.iz; });
    col_cell[c] = std::uint32_t(cell_start.size());
    for (auto it = b; it != e; ++it)
      if (it == b || it->iz != (it - 1)->iz) {
        cell_start.push_back(std::uint32_t(it - items.begin()));
        cell_iz.push_back(it->iz);
      }
  }
  col_cell[ncols] = std::uint32_t(cell_start.size());
  const std::size_t ncells = cell_start.size();
  cell_start.push_back(std::uint32_t(n));
  // Sorted copy of the coordinates for cache-friendly pair tests.
  std::vector<Xyz> sorted(n);
  for (std::size_t k = 0; k < n; ++k) sorted[k] = data.pts[items[k].idx];

  DisjointSets sets(ncells);
  auto try_link = [&](std::uint32_t a, std::uint32_t b) {
    if (sets.find(a) == sets.find(b)) return;
    for (std::uint32_t i = cell_start[a]; i < cell_start[a + 1]; ++i)
      for (std::uint32_t j = cell_start[b]; j < cell_start[b + 1]; ++j)
        if (squared_distance(sorted[i], sorted[j]) < r2) {
          sets.unite(a, b);
          return;
        }
  };
  // Neighbour columns in one half-plane (the other half sees this column from its side).
  static constexpr int kOffsets[12][2] = {{0, 1}, {0, 2},  {1, -2}, {1, -1}, {1, 0}, {1, 1},
                                          {1, 2}, {2, -2}, {2, -1}, {2, 0},  {2, 1}, {2, 2}};
  for (std::size_t c = 0; c < ncols; ++c) {
    const std::uint32_t c0 = col_cell[c], c1 = col_cell[c + 1];
    // Same column: cells one or two steps apart in z.
    for (std::uint32_t a = c0; a < c1; ++a)
      for (std::uint32_t b = a + 1; b < c1 && cell_iz[b] - cell_iz[a] <= 2; ++b) try_link(a, b);
    for (const auto& off : kOffsets) {
      const std::int32_t d = table.find(cix[c] + off[0], ciy[c] + off[1]);
      if (d < 0) continue;
      const std::uint32_t d0 = col_cell[d], d1 = col_cell[d + 1];
      std::uint32_t lo = d0;
      for (std::uint32_t a = c0; a < c1; ++a) {
        while (lo < d1 && cell_iz[lo] < cell_iz[a] - 2) ++lo;
        for (std::uint32_t b = lo; b < d1 && cell_iz[b] <= cell_iz[a] + 2; ++b) try_link(a, b);
      }
    }
  }
  std::vector<std::int32_t> root_id(ncells, -1);
  for (std::uint32_t cell = 0; cell < ncells; ++cell) {
    const std::uint32_t r = sets.find(cell);
    if (root_id[r] < 0) root_id[r] = std::int32_t(count++);
    const std::int32_t id = root_id[r];
    for (std::uint32_t k = cell_start[cell]; k < cell_start[cell + 1]; ++k) comp[items[k].idx] = id;
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
  // The points taking part, and their coordinates, in one pass over the cloud.
  std::vector<std::uint32_t> active;
  ActiveCloud data;
  active.reserve(cloud.size());
  data.pts.reserve(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Point& p = cloud.points[i];
    if ((skip.empty() || !skip[i]) && valid_point(p)) {
      active.push_back(std::uint32_t(i));
      data.pts.push_back({p.x, p.y, p.z});
    }
  }
  // pcl::KdTreeFLANN::radiusSearch hands FLANN static_cast<float>(radius * radius).
  const auto r2 = static_cast<float>(config.tolerance_m * config.tolerance_m);
  std::size_t count = 0;
  const std::vector<std::int32_t> local =
      config.search == EuclideanClusterConfig::Search::kKdTree
          ? components_kdtree(data, r2, count)
          : components_grid(data, config.tolerance_m, r2, count);
  std::vector<std::int32_t> component(cloud.size(), -1);
  for (std::size_t k = 0; k < active.size(); ++k) component[active[k]] = local[k];
  return make_clusters(cloud, component, count, config.min_points, config.max_points);
}

}  // namespace fieldlidar::segmentation
