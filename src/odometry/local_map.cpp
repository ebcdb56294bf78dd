// seed 002, step e / LOAM mapping: a voxel hash of world points, bounded by voxel capacity and by
// range around the robot, with line and plane fits over the nearest points.

#include "fieldlidar/odometry/local_map.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include <Eigen/Eigenvalues>

namespace fieldlidar::odometry {

VoxelMap::Key VoxelMap::key_of(const Eigen::Vector3f& p) const {
  const float inv = inv_voxel_;
  // floor without a libm call: truncate, then one down for negative non-integers.
  const auto fl = [](float v) {
    const auto i = std::int32_t(v);
    return i - std::int32_t(v < float(i));
  };
  return {fl(p.x() * inv), fl(p.y() * inv), fl(p.z() * inv)};
}

namespace {

std::size_t hash_key(std::int32_t x, std::int32_t y, std::int32_t z) {
  std::uint64_t h = std::uint64_t(std::uint32_t(x)) * 0x9E3779B97F4A7C15ull;
  h ^= std::uint64_t(std::uint32_t(y)) * 0xC2B2AE3D27D4EB4Full;
  h ^= std::uint64_t(std::uint32_t(z)) * 0x165667B19E3779F9ull;
  return std::size_t(h ^ (h >> 29));
}

}  // namespace

std::int32_t VoxelMap::find(const Key& k) const {
  if (table_.empty()) return -1;
  const std::size_t mask = table_.size() - 1;
  for (std::size_t i = hash_key(k.x, k.y, k.z) & mask;; i = (i + 1) & mask) {
    const Slot& slot = table_[i];
    if (slot.cell == 0) return -1;
    if (slot.key == k) return slot.cell - 1;
  }
}

std::int32_t VoxelMap::find_or_add(const Key& k) {
  if (2 * (cells_.size() + 1) > table_.size())
    rebuild_table(std::max<std::size_t>(64, 4 * cells_.size()));
  const std::size_t mask = table_.size() - 1;
  for (std::size_t i = hash_key(k.x, k.y, k.z) & mask;; i = (i + 1) & mask) {
    Slot& slot = table_[i];
    if (slot.cell != 0 && slot.key == k) return slot.cell - 1;
    if (slot.cell == 0) {
      cells_.push_back({k, 0, Eigen::Vector3f::Zero(), Eigen::Vector3f::Zero()});
      coords_.resize(cells_.size() * 3 * stride_, 0.f);
      slot = {k, std::int32_t(cells_.size())};
      return std::int32_t(cells_.size() - 1);
    }
  }
}

void VoxelMap::rebuild_table(std::size_t capacity) {
  std::size_t size = 64;
  while (size < capacity) size *= 2;
  table_.assign(size, Slot{});
  const std::size_t mask = size - 1;
  for (std::size_t c = 0; c < cells_.size(); ++c) {
    const Key& k = cells_[c].key;
    std::size_t i = hash_key(k.x, k.y, k.z) & mask;
    while (table_[i].cell != 0) i = (i + 1) & mask;
    table_[i] = {k, std::int32_t(c + 1)};
  }
}

void VoxelMap::clear() {
  cells_.clear();
  coords_.clear();
  table_.clear();
}

void VoxelMap::insert(std::span<const Eigen::Vector3f> points_world) {
  const float min2 = float(config_.min_point_spacing_m * config_.min_point_spacing_m);
  // Points come along scan lines: most fall in the voxel of the one before (no look-up then).
  Key last{0, 0, 0};
  std::int32_t last_cell = -1;
  for (const auto& p : points_world) {
    if (!p.allFinite()) continue;
    const Key key = key_of(p);
    if (last_cell < 0 || !(key == last)) {
      last = key;
      last_cell = find_or_add(key);
    }
    const auto c = std::size_t(last_cell);
    auto& cell = cells_[c];
    const std::uint32_t count = cell.count;
    if (count >= capacity_) continue;
    float* x = coordinates_of(c);
    float *y = x + stride_, *z = y + stride_;
    // Four held points at a time; the lanes past `count` do not count.
    bool near = false;
    for (std::uint32_t j0 = 0; j0 < count && !near; j0 += 4) {
      const Eigen::Array4f dx = Eigen::Array4f::Map(x + j0) - p.x();
      const Eigen::Array4f dy = Eigen::Array4f::Map(y + j0) - p.y();
      const Eigen::Array4f dz = Eigen::Array4f::Map(z + j0) - p.z();
      const Eigen::Array4f d2s = (dx * dx + dy * dy) + dz * dz;
      near = ((d2s < min2) && (Eigen::Array4f(0.f, 1.f, 2.f, 3.f) < float(count - j0))).any();
    }
    if (near) continue;
    cell.min = count == 0 ? p : Eigen::Vector3f(cell.min.cwiseMin(p));
    cell.max = count == 0 ? p : Eigen::Vector3f(cell.max.cwiseMax(p));
    x[count] = p.x();
    y[count] = p.y();
    z[count] = p.z();
    cell.count = count + 1;
  }
}

void VoxelMap::crop(const Eigen::Vector3d& centre_world) {
  const double r2 = config_.max_range_m * config_.max_range_m;
  const Eigen::Vector3f c = centre_world.cast<float>();
  const std::size_t before = cells_.size();
  std::size_t kept = 0;  // the voxels kept move to the front, in order, with their points
  const std::size_t block = 3 * stride_;
  for (std::size_t i = 0; i < before; ++i) {
    const float* v = coordinates_of(i);
    if (cells_[i].count == 0 ||
        double((Eigen::Vector3f(v[0], v[stride_], v[2 * stride_]) - c).squaredNorm()) > r2)
      continue;
    if (kept != i) {
      cells_[kept] = cells_[i];
      std::copy(v, v + block, coordinates_of(kept));
    }
    ++kept;
  }
  cells_.resize(kept);
  coords_.resize(kept * block);
  if (kept != before) rebuild_table(4 * kept);
}

std::size_t VoxelMap::nearest(const Eigen::Vector3f& query,
                              std::vector<Eigen::Vector3f>& out) const {
  // The k nearest among the 8 voxels nearest the query, by insertion into a short sorted list.
  // The voxels are visited nearest box first; once k points are found, a voxel whose box is
  // farther than the k-th of them cannot hold a nearer point and is passed over.
  const int k = std::clamp(config_.neighbours, 1, 16);
  const float max2 = float(config_.max_neighbour_distance_m * config_.max_neighbour_distance_m);
  // The best so far, nearest first: squared distances and where the points are.
  std::array<float, 16> best_d2;
  std::array<const float*, 16> best_x;  // a point's x (y and z stride_ and 2 stride_ on)
  int n = 0;
  const Key c = key_of(query);
  const float inv = inv_voxel_, side = 1.f / inv;
  // Position in the own voxel (0..1 of a side), the neighbour on the nearer side of each axis and
  // the squared distance (m^2) to the face shared with it.
  const Eigen::Vector3f f = query * inv - Eigen::Vector3f(float(c.x), float(c.y), float(c.z));
  int s[3];
  float face2[3];
  for (int a = 0; a < 3; ++a) {
    s[a] = f[a] < 0.5f ? -1 : 1;
    const float d = (f[a] < 0.5f ? f[a] : 1.f - f[a]) * side;
    face2[a] = d * d;
  }
  // The 8 voxels nearest box first, without a sort: with the faces' squared distances a <= b <=
  // c, the boxes' are 0 <= a <= b <= min(a + b, c) <= max(a + b, c) <= a + c <= b + c <= a + b + c.
  int ax[3] = {0, 1, 2};
  if (face2[ax[1]] < face2[ax[0]]) std::swap(ax[0], ax[1]);
  if (face2[ax[2]] < face2[ax[1]]) std::swap(ax[1], ax[2]);
  if (face2[ax[1]] < face2[ax[0]]) std::swap(ax[0], ax[1]);
  const int A = 4 >> ax[0], B = 4 >> ax[1], C = 4 >> ax[2];  // offset bits x|y|z
  const bool ab_first = face2[ax[0]] + face2[ax[1]] <= face2[ax[2]];
  const std::array<int, 8> order = {
      0, A, B, ab_first ? A | B : C, ab_first ? C : A | B, A | C, B | C, A | B | C};
  for (const int b : order) {
    // Each box's distance summed in one fixed order, so the bound tests below hold exactly.
    const float box2 =
        ((b & 4) ? face2[0] : 0.f) + ((b & 2) ? face2[1] : 0.f) + ((b & 1) ? face2[2] : 0.f);
    if (box2 > max2 || (n == k && box2 >= best_d2[k - 1])) continue;
    const std::int32_t cell =
        find({c.x + ((b & 4) ? s[0] : 0), c.y + ((b & 2) ? s[1] : 0), c.z + ((b & 1) ? s[2] : 0)});
    if (cell < 0) continue;
    const Cell& vox = cells_[std::size_t(cell)];
    if (n == k) {
      // Per axis the bound's gap is at most that of any point inside (float subtraction and the
      // sum below round monotonically), so the test below rejects every point it skips.
      const Eigen::Vector3f gap =
          (vox.min - query).cwiseMax(query - vox.max).cwiseMax(Eigen::Vector3f::Zero());
      if (gap.squaredNorm() >= best_d2[k - 1]) continue;
    }
    // Distances four points at a time (the same operations as (p - query).squaredNorm() per
    // lane), then the list kept as one point after the other.
    const float* x = coordinates_of(std::size_t(cell));
    const float *y = x + stride_, *z = y + stride_;
    for (std::uint32_t i0 = 0, m = vox.count; i0 < m; i0 += 4) {
      const Eigen::Array4f dx = Eigen::Array4f::Map(x + i0) - query.x();
      const Eigen::Array4f dy = Eigen::Array4f::Map(y + i0) - query.y();
      const Eigen::Array4f dz = Eigen::Array4f::Map(z + i0) - query.z();
      const Eigen::Array4f d2s = (dx * dx + dy * dy) + dz * dz;
      for (std::uint32_t i = i0, e = std::min(m, i0 + 4); i < e; ++i) {
        const float d2 = d2s[i - i0];
        // Until k are found every point within max2 enters; then only one nearer than the k-th
        // (which is within max2).
        if (n < k ? d2 > max2 : d2 >= best_d2[k - 1]) continue;
        int j = n < k ? n++ : k - 1;
        while (j > 0 && best_d2[j - 1] > d2) {
          best_d2[j] = best_d2[j - 1];
          best_x[j] = best_x[j - 1];
          --j;
        }
        best_d2[j] = d2;
        best_x[j] = x + i;
      }
    }
  }
  out.resize(std::size_t(n));
  for (int i = 0; i < n; ++i) {
    const float* p = best_x[std::size_t(i)];
    out[std::size_t(i)] = {p[0], p[stride_], p[2 * stride_]};
  }
  return out.size();
}

std::size_t VoxelMap::size() const {
  std::size_t n = 0;
  for (const auto& cell : cells_) n += cell.count;
  return n;
}

std::vector<Eigen::Vector3f> VoxelMap::points() const {
  std::vector<Eigen::Vector3f> out;
  out.reserve(size());
  for (std::size_t c = 0; c < cells_.size(); ++c) {
    const float* x = coordinates_of(c);
    for (std::uint32_t i = 0; i < cells_[c].count; ++i)
      out.emplace_back(x[i], x[i + stride_], x[i + 2 * stride_]);
  }
  return out;
}

void LocalMap::insert(std::span<const Eigen::Vector3f> edges_world,
                      std::span<const Eigen::Vector3f> planes_world) {
  edges_.insert(edges_world);
  planes_.insert(planes_world);
}

void LocalMap::crop(const Eigen::Vector3d& centre_world) {
  edges_.crop(centre_world);
  planes_.crop(centre_world);
}

void LocalMap::clear() {
  edges_.clear();
  planes_.clear();
}

namespace {

struct Fit {
  Eigen::Vector3d mean;
  Eigen::Matrix3d vectors;  ///< columns, ascending eigenvalue
  Eigen::Vector3d values;
};

Fit fit(const std::vector<Eigen::Vector3f>& pts) {
  Fit f;
  f.mean.setZero();
  for (const auto& p : pts) f.mean += p.cast<double>();
  f.mean /= double(pts.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& p : pts) {
    const Eigen::Vector3d d = p.cast<double>() - f.mean;
    cov.noalias() += d * d.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
  eig.computeDirect(cov / double(pts.size()));
  f.vectors = eig.eigenvectors();
  f.values = eig.eigenvalues();
  return f;
}

thread_local std::vector<Eigen::Vector3f> tls_scratch;

}  // namespace

std::optional<Correspondence> LocalMap::match_edge(const Eigen::Vector3f& point_world) const {
  auto& scratch = tls_scratch;  // one thread_local look-up per call
  if (edges_.nearest(point_world, scratch) < std::size_t(config_.neighbours)) return std::nullopt;
  const Fit f = fit(scratch);
  if (f.values(2) < config_.min_line_ratio * f.values(1)) return std::nullopt;
  return Correspondence{Eigen::Vector3d::Zero(), f.mean, f.vectors.col(2), true};
}

std::optional<Correspondence> LocalMap::match_plane(const Eigen::Vector3f& point_world) const {
  auto& scratch = tls_scratch;  // one thread_local look-up per call
  if (planes_.nearest(point_world, scratch) < std::size_t(config_.neighbours)) return std::nullopt;
  const Fit f = fit(scratch);
  if (f.values(1) < config_.min_plane_spread * f.values(2)) return std::nullopt;
  if (config_.max_plane_thickness_m > 0 &&
      f.values(0) > config_.max_plane_thickness_m * config_.max_plane_thickness_m)
    return std::nullopt;
  const Eigen::Vector3d n = f.vectors.col(0);
  for (const auto& p : scratch)
    if (std::abs(n.dot(p.cast<double>() - f.mean)) > config_.max_plane_distance_m)
      return std::nullopt;
  return Correspondence{Eigen::Vector3d::Zero(), f.mean, n, false};
}

PointCloud LocalMap::to_cloud() const {
  PointCloud cloud;
  cloud.fields.intensity = true;
  for (const auto& p : edges_.points()) cloud.push_back({p.x(), p.y(), p.z(), 1.f});
  for (const auto& p : planes_.points()) cloud.push_back({p.x(), p.y(), p.z(), 0.f});
  cloud.width = std::uint32_t(cloud.size());
  return cloud;
}

LocalMap LocalMap::from_cloud(const PointCloud& cloud, const LocalMapConfig& config) {
  LocalMap map(config);
  std::vector<Eigen::Vector3f> e, p;
  for (const auto& q : cloud.points) {
    if (!q.is_valid()) continue;
    (q.intensity == 1.f ? e : p).push_back(q.xyz());
  }
  map.insert(e, p);
  return map;
}

}  // namespace fieldlidar::odometry
