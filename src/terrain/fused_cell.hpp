#pragma once
/// \file The per-cell state of the fused map: sufficient statistics of the ground returns, the
/// obstacle evidence, and the layers last derived from them; cells kept in 32 x 32 tiles
/// allocated where scans land.

#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>

#include "fieldlidar/terrain/terrain_map.hpp"

namespace fieldlidar::terrain::detail {

/// Count, sum and sum of squares of 3D points: their mean and covariance, and the same of a union
/// of sets once each is shifted into a common frame.
struct PlaneSums {
  double n = 0;
  Eigen::Vector3d s = Eigen::Vector3d::Zero();
  Eigen::Matrix3d S = Eigen::Matrix3d::Zero();

  void add(const Eigen::Vector3d& p) {
    n += 1;
    s += p;
    S += p * p.transpose();
  }
  /// Adds `o`, whose points are `offset` away from this frame (p_here = p_there + offset).
  /// Written out per coefficient (the outer products as Eigen expressions made temporaries; this
  /// is the same arithmetic in the same order, so the same sums): the voxel window adds nine.
  void add_shifted(const PlaneSums& o, const Eigen::Vector3d& offset) {
    n += o.n;
    double v[3];  // o.n * offset
    for (int i = 0; i < 3; ++i) {
      v[i] = o.n * offset[i];
      s[i] += o.s[i] + v[i];
    }
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i)
        S(i, j) += o.S(i, j) + o.s[i] * offset[j] + offset[i] * o.s[j] + v[i] * offset[j];
  }
  Eigen::Vector3d mean() const { return s / n; }
  Eigen::Matrix3d covariance() const {
    const Eigen::Vector3d m = mean();
    return S / n - m * m.transpose();
  }
};

/// The order of the derived layers in FusedCell::layers (names in terrain::layer).
enum LayerIndex {
  kNx,
  kNy,
  kNz,
  kSlope,
  kRough,
  kRoughSum,
  kStep,
  kObst2d,
  kProj,
  kImpass,
  kTau,
  kElev,
  kLayerCount
};
inline constexpr std::array<const char*, kLayerCount> kLayerNames = {
    layer::kNormalX,           layer::kNormalY,      layer::kNormalZ,        layer::kSlopeDeg,
    layer::kRoughness,         layer::kRoughnessSum, layer::kStep,           layer::kObstacle2d,
    layer::kObstacleProjected, layer::kImpassable,   layer::kTraversability, layer::kElevation};

struct FusedCell {
  PlaneSums ground;  ///< ground returns relative to (cell centre x, y, z_ref)
  float z_ref = std::numeric_limits<float>::quiet_NaN();  ///< z of the first ground return
  float log_odds = 0.0f;                                  ///< obstacle evidence
  float obstacle_top_m = 0.0f;  ///< highest obstacle return above the ground while it holds
  std::uint32_t returns = 0;    ///< every return that fell in the cell
  bool bump = false;            ///< last derived as a bump obstacle (a low rock kept as ground)
  /// Deepest sunk beam seen over the cell in a trench shadow (m below the near ground; 0: none).
  float trench_depth_m = 0.0f;
  /// The highest ground return (z - z_ref): an overhang taken for ground (a branch seen before
  /// the ground under it) stands far above the ground a later scan sees there.
  float ground_max = -std::numeric_limits<float>::infinity();
  /// The lowest ground return (z - z_ref): the ground an overhang is judged against, which an
  /// overhang taken for ground in the same cell does not lift as it lifts the mean.
  float ground_min = std::numeric_limits<float>::infinity();
  /// The two highest ground returns (z - z_ref): the second is the cell's ground top, one stray
  /// return being no rock.
  std::array<float, 2> ground_top = {-std::numeric_limits<float>::infinity(),
                                     -std::numeric_limits<float>::infinity()};
  std::array<float, kLayerCount> layers;
  /// ground.mean() and ground.covariance(), refreshed when ground returns are added.
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();

  FusedCell() { layers.fill(std::numeric_limits<float>::quiet_NaN()); }
  void add_ground_top(float dz) { add_top(ground_top, dz); }
  static void add_top(std::array<float, 2>& top, float dz) {
    if (dz > top[0])
      top = {dz, top[0]};
    else if (dz > top[1])
      top[1] = dz;
  }
  /// The normal of the cell's own returns once derive_cell needed it, until they change (a cell
  /// is derived again whenever a neighbour in its window changes, its own plane mostly not).
  Eigen::Vector3d own_normal = Eigen::Vector3d::UnitZ();
  bool own_normal_fresh = false;
  void refresh_moments() {
    own_normal_fresh = false;
    mean = ground.mean();
    covariance = ground.covariance();
  }
};

/// Cells by integer index (ix, iy) = floor(xy / cell side), in tiles made on first write.
class CellStore {
 public:
  static constexpr int kTile = 32;

  FusedCell* find(int ix, int iy) {
    auto it = tiles_.find(key(ix, iy));
    return it == tiles_.end() ? nullptr : &(*it->second)[slot(ix, iy)];
  }
  const FusedCell* find(int ix, int iy) const {
    auto it = tiles_.find(key(ix, iy));
    return it == tiles_.end() ? nullptr : &(*it->second)[slot(ix, iy)];
  }
  FusedCell& get(int ix, int iy) {
    auto& tile = tiles_[key(ix, iy)];
    if (!tile) tile = std::make_unique<Tile>();
    if (empty_) lo_ = hi_ = Eigen::Vector2i(ix, iy), empty_ = false;
    lo_ = lo_.cwiseMin(Eigen::Vector2i(ix, iy));
    hi_ = hi_.cwiseMax(Eigen::Vector2i(ix, iy));
    return (*tile)[slot(ix, iy)];
  }
  bool empty() const { return empty_; }
  /// Cell columns ix and jx fall in the same tile.
  static bool same_tile(int ix, int jx) { return floor_div(ix) == floor_div(jx); }
  /// Smallest and largest cell index written.
  Eigen::Vector2i lo() const { return lo_; }
  Eigen::Vector2i hi() const { return hi_; }

 private:
  using Tile = std::array<FusedCell, kTile * kTile>;
  static int floor_div(int a) { return a >= 0 ? a / kTile : -((-a + kTile - 1) / kTile); }
  static std::int64_t key(int ix, int iy) {
    return (std::int64_t(floor_div(ix)) << 32) ^ std::int64_t(std::uint32_t(floor_div(iy)));
  }
  static int slot(int ix, int iy) {
    return (iy - floor_div(iy) * kTile) * kTile + (ix - floor_div(ix) * kTile);
  }
  std::unordered_map<std::int64_t, std::unique_ptr<Tile>> tiles_;
  Eigen::Vector2i lo_ = Eigen::Vector2i::Zero(), hi_ = Eigen::Vector2i::Zero();
  bool empty_ = true;
};

/// The cells of a rectangle of the store (w x h from index lo), each looked up once: derive_cell
/// reads about forty cells around each cell it derives, a hash lookup each from the store. Cells
/// outside the rectangle are found in the store. Valid until the store makes a new tile.
class CellBlock {
 public:
  CellBlock(CellStore& store, const Eigen::Vector2i& lo, int w, int h)
      : store_(store), lo_(lo), w_(w), h_(h), cells_(std::size_t(w) * h, nullptr) {
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const std::size_t k = std::size_t(y) * w + x;
        // One lookup per tile row segment: the next cells of the same tile follow in memory
        // (and a tile not made yet holds none of them).
        if (x > 0 && CellStore::same_tile(lo.x() + x - 1, lo.x() + x))
          cells_[k] = cells_[k - 1] ? cells_[k - 1] + 1 : nullptr;
        else
          cells_[k] = store.find(lo.x() + x, lo.y() + y);
      }
  }
  FusedCell* find(int ix, int iy) const {
    const int x = ix - lo_.x(), y = iy - lo_.y();
    if (x >= 0 && y >= 0 && x < w_ && y < h_) return cells_[std::size_t(y) * w_ + x];
    return store_.find(ix, iy);
  }

 private:
  CellStore& store_;
  Eigen::Vector2i lo_;
  int w_, h_;
  std::vector<FusedCell*> cells_;
};

/// What one scan saw in one cell.
struct ScanCell {
  FusedCell* cell = nullptr;
  std::uint32_t returns = 0, ground = 0, raised = 0;
  float low_ground = std::numeric_limits<float>::infinity();
  float top_m = 0.0f;  ///< highest obstacle return above the ground
  /// This scan's two highest ground returns (z - the cell's z_ref), kept as the cell's when the
  /// scan saw nothing raised there (a walker's feet are no rock).
  std::array<float, 2> ground_top = {-std::numeric_limits<float>::infinity(),
                                     -std::numeric_limits<float>::infinity()};
  bool seen_through = false;  ///< a ray crossed the cell's obstacle volume and ended beyond
  /// This scan's ground returns relative to (the cell's centre x, y; the sensor's z).
  PlaneSums scan_ground;
  /// The plane of this scan's ground returns in the 3 x 3 cells round this one
  /// (scan_ground_plane), worked out when a return first asks for it: z (relative to the
  /// sensor) at the cell's centre and its rise over x and y; NaN: none (too few returns, or
  /// steeper than the robot can climb).
  bool plane_done = false;
  float plane_z = std::numeric_limits<float>::quiet_NaN();
  float plane_dzdx = 0.0f, plane_dzdy = 0.0f;
};

/// The ground under a return at (dx, dy) m from cell (x, y)'s centre of the scan's window (w x h
/// cells) by the plane of this scan's ground returns in the 3 x 3 cells around it, z relative
/// to the sensor: NaN when they hold fewer than min_voxel_points returns or their plane is
/// steeper than the robot's max_slope_deg (a face or a wall: no ground to measure from).
double scan_ground_plane_z(std::span<ScanCell> local, int x, int y, int w, int h, double dx,
                           double dy, const FusionConfig& config);

/// The cells of the scan's window (w x h from cell index lo) that hold obstacle evidence and that
/// a return's ray (every `stride`-th, from sensor_m) crossed between min_obstacle_height and the
/// obstacle's top above the cell's ground without ending there: seen_through is set.
void mark_seen_through(std::span<ScanCell> local, const Eigen::Vector2i& lo, int w, int h,
                       std::span<const Eigen::Vector3d> points_m, const Eigen::Vector3d& sensor_m,
                       int stride, const FusionConfig& config);

/// The ground flags of a scan's returns (map frame; the cell of each finite one in `cells`, all
/// inside the w x h cells from index lo) less the overhangs the ground segmentation
/// took for ground (a branch over a track seen from afar, where the ground under it is hidden):
/// returns more than the robot's clearance above the lowest ground of their 3 x 3 cells, this
/// scan's or the store's (plus 2 sqrt 2 cells x tan(max_slope): ground the robot can climb rises
/// that much across them). A cell of the store whose ground stands as much above
/// this scan's lowest ground return in it (an overhang seen before the ground under it) loses
/// its ground statistics first.
std::vector<std::uint8_t> drop_overhang_ground(std::span<const Eigen::Vector3d> points_m,
                                               std::span<const std::uint8_t> is_ground,
                                               std::span<const Eigen::Vector2i> cells,
                                               const Eigen::Vector2i& lo, int w, int h,
                                               CellStore& store, const FusionConfig& config);

/// Recomputes the layers of cell (ix, iy) from its statistics and its voxel window's (`half`
/// cells each side; a no-op for a cell never written).
void derive_cell(const CellBlock& cells, int ix, int iy, int half, const FusionConfig& config);

}  // namespace fieldlidar::terrain::detail
