/// Scans into the fused map: per scan, the returns binned on a window of cells around the sensor,
/// ground returns added to their cells' statistics, obstacle evidence per cell, then the layers of
/// the touched cells and their voxel windows recomputed.
#include "fieldlidar/terrain/terrain_map.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/terrain/robot_config.hpp"
#include "fused_cell.hpp"
#include "scan_points.hpp"

namespace fieldlidar::terrain {

using detail::CellStore;
using detail::FusedCell;
using detail::ScanCell;

struct TerrainMap::Impl {
  FusionConfig config;
  CellStore store;
  std::size_t scans = 0;
  Eigen::Vector3d last_sensor_m = Eigen::Vector3d::Zero();
  double last_stamp_s = std::numeric_limits<double>::quiet_NaN();
  TrenchScratch trench_scratch;
};

namespace {

/// The cell of coordinate v (m); a coordinate a cell index cannot hold (more than 1e9 cells from
/// the origin: another unit than metres, a pose far off) is an error, not an overflowed int.
int cell_index(double v, double cell_m) {
  const double q = std::floor(v / cell_m);
  if (!(std::abs(q) < 1e9)) {
    char msg[160];
    std::snprintf(msg, sizeof msg,
                  "terrain fusion: a coordinate of %g m lies beyond 1e9 cells of %g m from the "
                  "map's origin (another unit than metres, or a pose far off?)",
                  v, cell_m);
    throw Error(msg);
  }
  return int(q);
}

/// The layers of the w x h cells from index lo on, as a Grid2D (cells never written unknown).
Grid2D copy_cells(const CellStore& store, const Eigen::Vector2i& lo, int w, int h, double cm) {
  GridGeometry g{.resolution_m = cm, .origin_m = lo.cast<double>() * cm, .width = w, .height = h};
  Grid2D map(g);
  std::array<std::span<float>, detail::kLayerCount> layers;
  for (int i = 0; i < detail::kLayerCount; ++i)
    layers[i] = map.add_layer(detail::kLayerNames[i], std::numeric_limits<float>::quiet_NaN());
  auto points = map.add_layer(layer::kPoints, 0.0f);
  auto negative = map.add_layer(layer::kNegativeObstacle, 0.0f);
  for (int iy = 0; iy < h; ++iy)
    for (int ix = 0; ix < w; ++ix) {
      const FusedCell* cell = store.find(lo.x() + ix, lo.y() + iy);
      if (!cell) continue;
      const std::size_t k = g.linear_index(ix, iy);
      for (int i = 0; i < detail::kLayerCount; ++i) layers[i][k] = cell->layers[i];
      points[k] = float(cell->returns);
      negative[k] = cell->trench_depth_m > 0.0f && std::isnan(cell->layers[detail::kTau]);
    }
  return map;
}

/// The cells of level ground lose their trench mark, then the cells under each trench shadow
/// (every quarter cell along it) take its depth.
void mark_trench_shadows(CellStore& store, const TrenchScan& scan,
                         std::span<const Eigen::Vector3d> pts, double cm) {
  for (std::uint32_t i : scan.level_ground)
    if (FusedCell* cell = store.find(cell_index(pts[i].x(), cm), cell_index(pts[i].y(), cm)))
      cell->trench_depth_m = 0.0f;
  for (const TrenchShadow& s : scan.shadows) {
    const Eigen::Vector2d d = s.to_m - s.from_m;
    const int steps = 1 + int(std::ceil(d.norm() / (0.25 * cm)));
    for (int k = 0; k <= steps; ++k) {
      const Eigen::Vector2d p = s.from_m + d * (double(k) / steps);
      FusedCell& cell = store.get(cell_index(p.x(), cm), cell_index(p.y(), cm));
      cell.trench_depth_m = std::max(cell.trench_depth_m, s.depth_m);
    }
  }
}

}  // namespace

TerrainMap::TerrainMap(FusionConfig config) : impl_(std::make_unique<Impl>()) {
  check_robot_config(config.layers.robot, "terrain fusion: robot");
  voxel_height_m(config.layers);  // and the cell
  if (!(config.local_side_m > 0 && config.local_side_m <= 1e4))
    throw Error("terrain fusion: local_side_m = " + std::to_string(config.local_side_m) +
                " is outside (0, 10000]");
  if (!(config.hit_log_odds > 0 && config.miss_log_odds < 0 && config.min_log_odds < 0 &&
        config.max_log_odds > 0))
    throw Error(
        "terrain fusion: hit_log_odds and max_log_odds must be > 0, miss_log_odds and "
        "min_log_odds < 0");
  if (!(config.evidence_period_s >= 0 && config.evidence_period_s <= 1e3))
    throw Error("terrain fusion: evidence_period_s = " + std::to_string(config.evidence_period_s) +
                " is outside [0, 1000] s");
  impl_->config = config;
}
TerrainMap::~TerrainMap() = default;
TerrainMap::TerrainMap(TerrainMap&&) noexcept = default;
TerrainMap& TerrainMap::operator=(TerrainMap&&) noexcept = default;

std::size_t TerrainMap::scans() const {
  return impl_->scans;
}
const FusionConfig& TerrainMap::config() const {
  return impl_->config;
}

FusionUpdate TerrainMap::add_scan(const PointCloud& scan, const SensorModel& sensor,
                                  const Pose& T_map_lidar) {
  const ScanPoints in_map = scan_points_in_map(scan, sensor, T_map_lidar, impl_->config.layers);
  return add_points(in_map.points_m, in_map.is_ground, T_map_lidar.translation(), scan.stamp_s);
}

FusionUpdate TerrainMap::add_points(std::span<const Eigen::Vector3d> pts,
                                    std::span<const std::uint8_t> is_ground,
                                    const Eigen::Vector3d& sensor_m, double stamp_s) {
  if (is_ground.size() != pts.size())
    throw Error("terrain fusion: " + std::to_string(is_ground.size()) + " ground flags for " +
                std::to_string(pts.size()) + " points");
  const FusionConfig& f = impl_->config;
  const TraversabilityConfig& c = f.layers;
  const double cm = c.cell_m;
  FusionUpdate u;
  // The scan's window of cells: its finite returns' extent.
  Eigen::Vector2i lo(0, 0), hi(-1, -1);
  std::vector<Eigen::Vector2i> cell_of(pts.size());  // each return's cell (finite returns)
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const Eigen::Vector3d& p = pts[i];
    if (!p.allFinite()) continue;
    const Eigen::Vector2i k(cell_index(p.x(), cm), cell_index(p.y(), cm));
    cell_of[i] = k;
    if (u.points++ == 0) lo = hi = k;
    lo = lo.cwiseMin(k);
    hi = hi.cwiseMax(k);
  }
  ++impl_->scans;
  impl_->last_sensor_m = sensor_m;
  // The share of a whole scan's evidence this one adds (FusionConfig::evidence_period_s).
  const double dt = stamp_s - impl_->last_stamp_s;
  const float weight =
      f.evidence_period_s > 0 && dt > 0 ? float(std::min(1.0, dt / f.evidence_period_s)) : 1.0f;
  if (std::isfinite(stamp_s)) impl_->last_stamp_s = stamp_s;
  if (u.points == 0) return u;
  const int w = hi.x() - lo.x() + 1, h = hi.y() - lo.y() + 1;
  if (double(w) * h > 4e7)
    throw Error("terrain fusion: one scan spans " + std::to_string(w) + " x " + std::to_string(h) +
                " cells; far-off points? (max_range_m bounds add_scan)");
  std::vector<ScanCell> local(std::size_t(w) * h);
  auto local_of = [&](std::size_t i) -> ScanCell& {
    return local[std::size_t(cell_of[i].y() - lo.y()) * w + (cell_of[i].x() - lo.x())];
  };

  // Ground returns into their cells' statistics (relative to the cell centre and z_ref), less
  // the overhangs the ground segmentation took for ground.
  const std::vector<std::uint8_t> ground_flags =
      detail::drop_overhang_ground(pts, is_ground, cell_of, lo, w, h, impl_->store, f);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const Eigen::Vector3d& p = pts[i];
    if (!p.allFinite()) continue;
    ScanCell& s = local_of(i);
    const int ix = cell_of[i].x(), iy = cell_of[i].y();
    if (!s.cell) s.cell = &impl_->store.get(ix, iy);
    ++s.returns;
    if (!ground_flags[i]) continue;
    ++s.ground;
    ++u.ground_points;
    s.low_ground = std::min(s.low_ground, float(p.z()));
    s.scan_ground.add({p.x() - (ix + 0.5) * cm, p.y() - (iy + 0.5) * cm, p.z() - sensor_m.z()});
    FusedCell& cell = *s.cell;
    if (std::isnan(cell.z_ref)) cell.z_ref = float(p.z());
    cell.ground.add({p.x() - (ix + 0.5) * cm, p.y() - (iy + 0.5) * cm, p.z() - cell.z_ref});
    cell.ground_max = std::max(cell.ground_max, float(p.z() - cell.z_ref));
    cell.ground_min = std::min(cell.ground_min, float(p.z() - cell.z_ref));
    FusedCell::add_top(s.ground_top, float(p.z() - cell.z_ref));
  }
  // Obstacle returns: between min_obstacle_height and clearance above the cell's ground (its
  // plane from earlier scans under the return, else this scan's lowest ground return there, else
  // the map's elevation).
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const Eigen::Vector3d& p = pts[i];
    if (ground_flags[i] || !p.allFinite()) continue;
    ScanCell& s = local_of(i);
    const auto& known = s.cell->layers;
    double base = s.low_ground;
    if (f.obstacle_height_from_plane && std::isfinite(known[detail::kElev]) &&
        known[detail::kNz] > 0.5f) {  // the cell's ground plane under the return
      const double dx = p.x() - (cell_of[i].x() + 0.5) * cm;
      const double dy = p.y() - (cell_of[i].y() + 0.5) * cm;
      base = known[detail::kElev] -
             (known[detail::kNx] * dx + known[detail::kNy] * dy) / known[detail::kNz];
    }
    if (!std::isfinite(base)) base = known[detail::kElev];
    if (!std::isfinite(base)) {  // the lowest ground this scan saw next to the cell
      const int x = cell_of[i].x() - lo.x(), y = cell_of[i].y() - lo.y();
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          if (x + dx >= 0 && y + dy >= 0 && x + dx < w && y + dy < h)
            base = std::fmin(base, local[std::size_t(y + dy) * w + x + dx].low_ground);
      if (!std::isfinite(base) && f.obstacle_height_from_plane)  // else the map's there
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx)
            if (const FusedCell* q = impl_->store.find(lo.x() + x + dx, lo.y() + y + dy))
              base = std::fmin(base, q->layers[detail::kElev]);
    }
    if (f.obstacle_height_from_scan_plane) {  // the local ground's slope lifts the base
      const int x = cell_of[i].x() - lo.x(), y = cell_of[i].y() - lo.y();
      const double plane =
          scan_ground_plane_z(local, x, y, w, h, p.x() - (cell_of[i].x() + 0.5) * cm,
                              p.y() - (cell_of[i].y() + 0.5) * cm, f) +
          sensor_m.z();
      if (std::isfinite(plane)) base = std::isfinite(base) ? std::max(base, plane) : plane;
    }
    if (!std::isfinite(base)) continue;
    const double above = p.z() - base;
    // Up into the robot's body, or down a pit's wall beyond the step it can take.
    if (above >= c.robot.min_obstacle_height_m && above <= c.robot.clearance_m) {
      ++s.raised;
      s.top_m = std::max(s.top_m, float(above));
    } else if (f.pit_evidence && above < -c.robot.max_step_m) {
      ++s.raised;
    }
  }
  if (f.negative_obstacles.enabled) {
    // Ground returns in a cell holding an obstacle return of this scan or obstacle evidence
    // (a rock's or bush's top kept as ground) are no ground to judge a trench by.
    std::vector<std::uint8_t> clear_ground(ground_flags);
    for (std::size_t i = 0; i < pts.size(); ++i)
      if (clear_ground[i] && (local_of(i).raised > 0 || local_of(i).cell->log_odds > 0.0f))
        clear_ground[i] = 0;
    mark_trench_shadows(impl_->store,
                        find_trench_shadows(pts, clear_ground, sensor_m, c.robot.max_slope_deg,
                                            f.negative_obstacles, impl_->trench_scratch),
                        pts, cm);
  }
  if (f.see_through_stride > 0)
    detail::mark_seen_through(local, lo, w, h, pts, sensor_m, f.see_through_stride, f);
  // Evidence per cell, then the layers of every cell whose ground or evidence changed and of
  // the cells whose voxel window (or obstacle halo) holds one: the scan's window padded by `pad`.
  const int half = int(std::lround(voxel_side_m(c) / cm)) / 2, pad = std::max(half, 1);
  const int pw = w + 2 * pad, ph = h + 2 * pad;
  std::vector<std::uint8_t> dirty(std::size_t(pw) * ph, 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      ScanCell& s = local[std::size_t(y) * w + x];
      if (!s.cell) continue;
      ++u.cells_touched;
      FusedCell& cell = *s.cell;
      cell.returns += s.returns;
      if (s.ground > 0) cell.refresh_moments();
      if (s.raised == 0)
        for (float z : s.ground_top) cell.add_ground_top(z);
      const float before = cell.log_odds;
      if (int(s.raised) >= c.min_obstacle_points) {
        cell.log_odds = std::min(f.max_log_odds, cell.log_odds + weight * f.hit_log_odds);
        cell.obstacle_top_m = std::max(cell.obstacle_top_m, s.top_m);
      } else if (int(s.ground) >= f.min_free_ground_points || s.seen_through) {
        cell.log_odds = std::max(f.min_log_odds, cell.log_odds + weight * f.miss_log_odds);
        if (cell.log_odds <= 0.0f) cell.obstacle_top_m = 0.0f;
      }
      if (s.ground == 0 && cell.log_odds == before) continue;
      for (int dy = -pad; dy <= pad; ++dy)
        for (int dx = -pad; dx <= pad; ++dx)
          dirty[std::size_t(y + pad + dy) * pw + (x + pad + dx)] = 1;
    }
  // Every cell derive_cell reads: the dirty cells, the rims below, and their windows and halos.
  const int reach = pad + 1 + std::max(half, 1);
  const detail::CellBlock cells(impl_->store, lo - Eigen::Vector2i(reach, reach), w + 2 * reach,
                                h + 2 * reach);
  std::vector<Eigen::Vector2i> rims;  // 4-neighbours of cells that became or stopped being bumps
  for (int y = 0; y < ph; ++y)
    for (int x = 0; x < pw; ++x)
      if (dirty[std::size_t(y) * pw + x]) {
        const int ix = lo.x() + x - pad, iy = lo.y() + y - pad;
        const FusedCell* cell = cells.find(ix, iy);
        const bool bump = cell && cell->bump;
        detail::derive_cell(cells, ix, iy, half, f);
        ++u.cells_updated;
        if (cell && cell->bump != bump)
          for (const auto& [dx, dy] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}})
            rims.emplace_back(ix + dx, iy + dy);
      }
  // A bump's rim blocks too (derive_cell's halo), read from the neighbour's flag: the rims of
  // this scan's new or gone bumps once more, now that every flag is current.
  for (const auto& c : rims) detail::derive_cell(cells, c.x(), c.y(), half, f);
  return u;
}

Grid2D TerrainMap::local_map(const Eigen::Vector2d& center_m, double side_m) const {
  const double cm = impl_->config.layers.cell_m;
  const Eigen::Vector2i lo(cell_index(center_m.x() - side_m / 2, cm),
                           cell_index(center_m.y() - side_m / 2, cm));
  const int n = std::max(1, int(std::ceil(side_m / cm)));
  return copy_cells(impl_->store, lo, n, n, cm);
}

Grid2D TerrainMap::local_map() const {
  return local_map(impl_->last_sensor_m.head<2>(), impl_->config.local_side_m);
}

Grid2D TerrainMap::global_map() const {
  const double cm = impl_->config.layers.cell_m;
  if (impl_->store.empty()) return Grid2D(GridGeometry{.resolution_m = cm});
  const Eigen::Vector2i lo = impl_->store.lo(), hi = impl_->store.hi();
  return copy_cells(impl_->store, lo, hi.x() - lo.x() + 1, hi.y() - lo.y() + 1, cm);
}

}  // namespace fieldlidar::terrain
