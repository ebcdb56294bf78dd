/// Steps b-d of seed 004 over the cells of one grid: a robot-sized voxel centred on each cell,
/// placed on the window's lowest ground, its plane (PCA), the cell's points against that plane.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Eigenvalues>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/terrain/robot_config.hpp"
#include "fieldlidar/terrain/traversability.hpp"
#include "plane_normal.hpp"

namespace fieldlidar::terrain {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr double kDeg = std::numbers::pi / 180.0;

void check_range(const char* field, double v, double lo, double hi) {
  if (!(v > lo && v <= hi))
    throw Error("terrain config: " + std::string(field) + " = " + std::to_string(v) +
                " is outside (" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
}

}  // namespace

TraversabilityConfig seed004_config() {
  TraversabilityConfig c;
  c.project_obstacles = false;
  c.ground_plane = false;
  c.voxel_step = false;
  c.min_plane_spread_m = 0.0;
  return c;
}

double voxel_side_m(const TraversabilityConfig& c) {
  check_range("robot.length_m", c.robot.length_m, 0.0, 20.0);
  check_range("robot.width_m", c.robot.width_m, 0.0, 20.0);
  check_range("cell_m", c.cell_m, 0.0, 10.0);
  if (!(c.min_plane_spread_m >= 0.0 && c.min_plane_spread_m <= 10.0))
    throw Error("terrain config: min_plane_spread_m = " + std::to_string(c.min_plane_spread_m) +
                " is outside [0, 10]");
  const double diagonal = std::hypot(c.robot.length_m, c.robot.width_m);
  int cells = int(std::ceil(diagonal / c.cell_m - 1e-9));
  if (cells % 2 == 0) ++cells;
  return cells * c.cell_m;
}

double voxel_height_m(const TraversabilityConfig& c) {
  check_range("robot.max_slope_deg", c.robot.max_slope_deg, 0.0, 79.999);
  check_range("robot.max_step_m", c.robot.max_step_m, 0.0, 5.0);
  return voxel_side_m(c) * std::tan(c.robot.max_slope_deg * kDeg);
}

namespace {

/// The points binned by cell (counting sort), with each cell's lowest ground return and lowest
/// return of any kind.
struct CellBins {
  std::vector<std::uint32_t> start;  ///< points of cell k: order[start[k] .. start[k + 1])
  std::vector<std::uint32_t> order;
  std::vector<float> low_ground, low_any;
  int count(std::size_t k) const { return int(start[k + 1] - start[k]); }
};

CellBins bin_points(std::span<const Eigen::Vector3d> pts, std::span<const std::uint8_t> ground,
                    const GridGeometry& g) {
  const std::size_t n_cells = g.cell_count();
  CellBins b;
  b.start.assign(n_cells + 1, 0);
  b.low_ground.assign(n_cells, std::numeric_limits<float>::infinity());
  b.low_any.assign(n_cells, std::numeric_limits<float>::infinity());
  std::vector<std::int64_t> cell_of(pts.size(), -1);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (!pts[i].allFinite()) continue;
    const auto cell = g.cell_of(pts[i].head<2>());
    if (!cell) continue;
    const std::size_t k = g.linear_index(cell->x(), cell->y());
    cell_of[i] = std::int64_t(k);
    ++b.start[k + 1];
    b.low_any[k] = std::min(b.low_any[k], float(pts[i].z()));
    if (ground[i]) b.low_ground[k] = std::min(b.low_ground[k], float(pts[i].z()));
  }
  for (std::size_t k = 0; k < n_cells; ++k) b.start[k + 1] += b.start[k];
  b.order.resize(b.start[n_cells]);
  std::vector<std::uint32_t> fill(b.start.begin(), b.start.end() - 1);
  for (std::size_t i = 0; i < pts.size(); ++i)
    if (cell_of[i] >= 0) b.order[fill[std::size_t(cell_of[i])]++] = std::uint32_t(i);
  return b;
}

/// Calls f(point index) for every point binned in the window of cells of half-width `half`
/// around (ix, iy).
template <class F>
void for_each_in_window(const CellBins& b, const GridGeometry& g, int ix, int iy, int half, F&& f) {
  for (int dy = -half; dy <= half; ++dy)
    for (int dx = -half; dx <= half; ++dx) {
      if (!g.contains(ix + dx, iy + dy)) continue;
      const std::size_t q = g.linear_index(ix + dx, iy + dy);
      for (std::uint32_t j = b.start[q]; j < b.start[q + 1]; ++j) f(b.order[j]);
    }
}

/// Step b: the voxel centred on a cell, from its window's lowest ground up g_h, and its planes.
struct VoxelFit {
  double lo = 0, hi = 0, z0 = 0;     ///< pass-through band (m) and the window's lowest ground
  Eigen::Vector3d centroid, normal;  ///< the slope's plane (ground returns when enough)
  double rho = 0;                    ///< its slope (deg)
  bool ground_plane = false;         ///< normal from the voxel's ground returns only
  bool too_steep = false;            ///< the seed's 2D obstacle (voxel or ground plane)
};

/// Unit normal (z >= 0) and centroid of a point set's sums.
Eigen::Vector3d fit_plane(const Eigen::Vector3d& s1, const Eigen::Matrix3d& s2, int count,
                          double min_spread_m, Eigen::Vector3d& centroid) {
  centroid = s1 / count;
  const Eigen::Matrix3d cov = s2 / count - centroid * centroid.transpose();
  return detail::plane_normal(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov), min_spread_m);
}

/// nullopt when the voxel holds fewer than min_voxel_points.
std::optional<VoxelFit> fit_voxel(const CellBins& b, std::span<const Eigen::Vector3d> pts,
                                  std::span<const std::uint8_t> ground, const GridGeometry& g,
                                  int ix, int iy, int half, double g_h,
                                  const TraversabilityConfig& c) {
  float z0 = std::numeric_limits<float>::infinity(), z0_any = z0;
  for (int dy = -half; dy <= half; ++dy)
    for (int dx = -half; dx <= half; ++dx) {
      if (!g.contains(ix + dx, iy + dy)) continue;
      const std::size_t q = g.linear_index(ix + dx, iy + dy);
      z0 = std::min(z0, b.low_ground[q]);
      z0_any = std::min(z0_any, b.low_any[q]);
    }
  if (!std::isfinite(z0)) z0 = z0_any;  // no ground under the window: its lowest return
  VoxelFit v;
  v.z0 = z0;
  v.lo = z0 - c.below_ground_m;
  v.hi = z0 + g_h;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero(), gsum = sum;
  Eigen::Matrix3d sq = Eigen::Matrix3d::Zero(), gsq = sq;
  int n = 0, gn = 0;
  for_each_in_window(b, g, ix, iy, half, [&](std::uint32_t i) {
    const Eigen::Vector3d& p = pts[i];
    if (p.z() < v.lo || p.z() > v.hi) return;  // pass-through: overhangs fall out
    sum += p;
    sq += p * p.transpose();
    ++n;
    if (ground[i]) {
      gsum += p;
      gsq += p * p.transpose();
      ++gn;
    }
  });
  if (n < c.min_voxel_points) return std::nullopt;
  // The seed's voxel plane (all points in the voxel) decides the 2D obstacle; the ground's own
  // plane (its ground returns, when enough) gives the slope of the ground there.
  Eigen::Vector3d voxel_centroid;
  const Eigen::Vector3d voxel_normal = fit_plane(sum, sq, n, c.min_plane_spread_m, voxel_centroid);
  v.ground_plane = c.ground_plane && gn >= c.min_voxel_points;
  v.normal =
      v.ground_plane ? fit_plane(gsum, gsq, gn, c.min_plane_spread_m, v.centroid) : voxel_normal;
  if (!v.ground_plane) v.centroid = voxel_centroid;
  const double rho_voxel = std::acos(std::clamp(voxel_normal.z(), -1.0, 1.0)) / kDeg;
  v.rho = std::acos(std::clamp(v.normal.z(), -1.0, 1.0)) / kDeg;
  v.too_steep = rho_voxel > c.robot.max_slope_deg || v.rho > c.robot.max_slope_deg;
  return v;
}

/// Step c and claim 5: a cell's returns against its voxel's plane.
struct CellMeasure {
  int in_voxel = 0;  ///< the cell's returns inside the voxel (0: overhang only)
  double step = 0, roughness = 0, roughness_sum = 0, plane_z = 0;
  bool projected = false;  ///< enough obstacle returns (min_obstacle_height .. clearance)
};

CellMeasure measure_cell(const CellBins& b, std::span<const Eigen::Vector3d> pts,
                         std::span<const std::uint8_t> ground, const GridGeometry& g, int ix,
                         int iy, int half, const VoxelFit& v, const TraversabilityConfig& c) {
  const std::size_t k = g.linear_index(ix, iy);
  const Eigen::Vector2d centre = g.cell_center(ix, iy);
  const Eigen::Vector3d& n = v.normal;
  CellMeasure m;
  m.plane_z = std::abs(n.z()) > 0.05 ? v.centroid.z() - (n.x() * (centre.x() - v.centroid.x()) +
                                                         n.y() * (centre.y() - v.centroid.y())) /
                                                            n.z()
                                     : v.z0;
  const double cell_ground = std::isfinite(b.low_ground[k]) ? b.low_ground[k] : m.plane_z;
  // Step or pit: the height range of the voxel's points about its plane (the cell and its
  // neighbours, as far as the robot reaches).
  double vmin = 0, vmax = 0;
  int vm = 0;
  for_each_in_window(b, g, ix, iy, half, [&](std::uint32_t i) {
    const Eigen::Vector3d& p = pts[i];
    if (p.z() < v.lo || p.z() > v.hi || (v.ground_plane && !ground[i])) return;
    const double d = n.dot(p - v.centroid);
    vmin = vm ? std::min(vmin, d) : d;
    vmax = vm ? std::max(vmax, d) : d;
    ++vm;
  });
  double dmin = 0, dmax = 0, dsum = 0;
  int raised = 0;
  for (std::uint32_t j = b.start[k]; j < b.start[k + 1]; ++j) {
    const Eigen::Vector3d& p = pts[b.order[j]];
    const double above = p.z() - cell_ground;
    if (!ground[b.order[j]] && above >= c.robot.min_obstacle_height_m &&
        above <= c.robot.clearance_m)
      ++raised;
    if (p.z() < v.lo || p.z() > v.hi) continue;
    const double d = n.dot(p - v.centroid);
    dmin = m.in_voxel ? std::min(dmin, d) : d;
    dmax = m.in_voxel ? std::max(dmax, d) : d;
    dsum += std::abs(d);
    ++m.in_voxel;
  }
  if (m.in_voxel == 0) return m;
  m.step = c.voxel_step ? vmax - vmin : dmax - dmin;
  m.roughness = dsum / m.in_voxel;
  m.roughness_sum = dsum;
  m.projected = c.project_obstacles && raised >= c.min_obstacle_points;
  return m;
}

/// The layers' spans, NaN (unknown) everywhere but "points" (0).
struct LayerSpans {
  std::span<float> nx, ny, nz, slope, rough, rsum, step, obst2d, proj, impass, tau, elev, count;
};

LayerSpans add_layers(Grid2D& map) {
  auto add = [&](const char* name) { return map.add_layer(name, kNaN); };
  return {add(layer::kNormalX),
          add(layer::kNormalY),
          add(layer::kNormalZ),
          add(layer::kSlopeDeg),
          add(layer::kRoughness),
          add(layer::kRoughnessSum),
          add(layer::kStep),
          add(layer::kObstacle2d),
          add(layer::kObstacleProjected),
          add(layer::kImpassable),
          add(layer::kTraversability),
          add(layer::kElevation),
          map.add_layer(layer::kPoints, 0.f)};
}

/// Step d for one known cell: the layers from its voxel and its measures; tau per the config.
void write_cell(const LayerSpans& L, std::size_t k, const VoxelFit& v, const CellMeasure& m,
                const TraversabilityConfig& c) {
  L.nx[k] = float(v.normal.x());
  L.ny[k] = float(v.normal.y());
  L.nz[k] = float(v.normal.z());
  L.slope[k] = float(v.rho);
  L.obst2d[k] = v.too_steep ? 1.f : 0.f;
  L.step[k] = float(m.step);
  L.rough[k] = float(m.roughness);
  L.rsum[k] = float(m.roughness_sum);
  L.elev[k] = float(m.plane_z);
  L.proj[k] = m.projected ? 1.f : 0.f;
  const bool blocked = v.too_steep || m.step > c.robot.max_step_m || m.projected;
  L.impass[k] = blocked ? 1.f : 0.f;
  const double rho_max = c.robot.max_slope_deg, r_scale = c.robot.max_step_m / 2.0;
  L.tau[k] = blocked ? 0.f
                     : float(std::clamp(1.0 - c.weight_slope * v.rho / rho_max -
                                            c.weight_roughness * m.roughness / r_scale,
                                        0.0, 1.0));
}

}  // namespace

Grid2D build_layers(std::span<const Eigen::Vector3d> pts, std::span<const std::uint8_t> ground,
                    const GridGeometry& g, const TraversabilityConfig& c) {
  check_robot_config(c.robot, "terrain config: robot");
  const double g_l = voxel_side_m(c);
  const double g_h = voxel_height_m(c);
  if (ground.size() != pts.size()) throw Error("terrain: ground flags do not match the points");
  Grid2D map(g);
  const LayerSpans layers = add_layers(map);
  if (g.cell_count() == 0) return map;
  const CellBins bins = bin_points(pts, ground, g);
  const int half = int(std::lround(g_l / c.cell_m)) / 2;
  for (int iy = 0; iy < g.height; ++iy)
    for (int ix = 0; ix < g.width; ++ix) {
      const std::size_t k = g.linear_index(ix, iy);
      layers.count[k] = float(bins.count(k));
      if (bins.count(k) < c.min_cell_points) continue;
      const auto voxel = fit_voxel(bins, pts, ground, g, ix, iy, half, g_h, c);
      if (!voxel) continue;
      const CellMeasure m = measure_cell(bins, pts, ground, g, ix, iy, half, *voxel, c);
      if (m.in_voxel == 0) continue;  // the cell's returns all lie above its voxel: unknown
      write_cell(layers, k, *voxel, m, c);
    }
  return map;
}

}  // namespace fieldlidar::terrain
