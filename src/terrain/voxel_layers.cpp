/// Steps b-d of seed 004 over the cells of one grid: a robot-sized voxel centred on each cell,
/// placed on the window's lowest ground, its plane (PCA), the cell's points against that plane.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Eigenvalues>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/terrain/traversability.hpp"

namespace fieldlidar::terrain {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr double kDeg = 3.14159265358979323846 / 180.0;

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
  return c;
}

double voxel_side_m(const TraversabilityConfig& c) {
  check_range("robot.length_m", c.robot.length_m, 0.0, 20.0);
  check_range("robot.width_m", c.robot.width_m, 0.0, 20.0);
  check_range("cell_m", c.cell_m, 0.0, 10.0);
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

Grid2D build_layers(std::span<const Eigen::Vector3d> pts, std::span<const std::uint8_t> ground,
                    const GridGeometry& g, const TraversabilityConfig& c) {
  const double g_l = voxel_side_m(c);
  const double g_h = voxel_height_m(c);
  if (ground.size() != pts.size()) throw Error("terrain: ground flags do not match the points");
  Grid2D map(g);
  for (const char* name :
       {layer::kNormalX, layer::kNormalY, layer::kNormalZ, layer::kSlopeDeg, layer::kRoughness,
        layer::kRoughnessSum, layer::kStep, layer::kObstacle2d, layer::kObstacleProjected,
        layer::kImpassable, layer::kTraversability, layer::kElevation})
    map.add_layer(name, kNaN);
  auto count = map.add_layer(layer::kPoints, 0.f);
  const std::size_t n_cells = g.cell_count();
  if (n_cells == 0) return map;

  // Bin the points by cell (counting sort), and the lowest ground return of each cell.
  std::vector<std::uint32_t> start(n_cells + 1, 0);
  std::vector<std::int64_t> cell_of(pts.size(), -1);
  std::vector<float> low_ground(n_cells, std::numeric_limits<float>::infinity());
  std::vector<float> low_any(n_cells, std::numeric_limits<float>::infinity());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (!pts[i].allFinite()) continue;
    const auto cell = g.cell_of(pts[i].head<2>());
    if (!cell) continue;
    const std::size_t k = g.linear_index(cell->x(), cell->y());
    cell_of[i] = std::int64_t(k);
    ++start[k + 1];
    low_any[k] = std::min(low_any[k], float(pts[i].z()));
    if (ground[i]) low_ground[k] = std::min(low_ground[k], float(pts[i].z()));
  }
  for (std::size_t k = 0; k < n_cells; ++k) start[k + 1] += start[k];
  std::vector<std::uint32_t> order(start[n_cells]);
  {
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::size_t i = 0; i < pts.size(); ++i)
      if (cell_of[i] >= 0) order[fill[std::size_t(cell_of[i])]++] = std::uint32_t(i);
  }

  const int half = int(std::lround(g_l / c.cell_m)) / 2;
  // Calls f(point index) for every point binned in the voxel's window of cells around (ix, iy).
  auto for_each_in_window = [&](int ix, int iy, auto&& f) {
    for (int dy = -half; dy <= half; ++dy)
      for (int dx = -half; dx <= half; ++dx) {
        if (!g.contains(ix + dx, iy + dy)) continue;
        const std::size_t q = g.linear_index(ix + dx, iy + dy);
        for (std::uint32_t j = start[q]; j < start[q + 1]; ++j) f(order[j]);
      }
  };
  const double rho_max = c.robot.max_slope_deg;
  const double r_scale = c.robot.max_step_m / 2.0;
  auto L = [&](const char* name) { return map.layer(name); };
  auto nx = L(layer::kNormalX), ny = L(layer::kNormalY), nz = L(layer::kNormalZ);
  auto slope = L(layer::kSlopeDeg), rough = L(layer::kRoughness), rsum = L(layer::kRoughnessSum);
  auto step = L(layer::kStep), obst2d = L(layer::kObstacle2d), proj = L(layer::kObstacleProjected);
  auto impass = L(layer::kImpassable), tau = L(layer::kTraversability), elev = L(layer::kElevation);

  for (int iy = 0; iy < g.height; ++iy) {
    for (int ix = 0; ix < g.width; ++ix) {
      const std::size_t k = g.linear_index(ix, iy);
      const int own = int(start[k + 1] - start[k]);
      count[k] = float(own);
      if (own < c.min_cell_points) continue;
      // Step b: the voxel centred on the cell, from the window's lowest ground up g_h.
      float z0 = std::numeric_limits<float>::infinity(), z0_any = z0;
      for (int dy = -half; dy <= half; ++dy)
        for (int dx = -half; dx <= half; ++dx) {
          if (!g.contains(ix + dx, iy + dy)) continue;
          const std::size_t q = g.linear_index(ix + dx, iy + dy);
          z0 = std::min(z0, low_ground[q]);
          z0_any = std::min(z0_any, low_any[q]);
        }
      if (!std::isfinite(z0)) z0 = z0_any;  // no ground under the window: its lowest return
      const double lo = z0 - c.below_ground_m, hi = z0 + g_h;
      Eigen::Vector3d sum = Eigen::Vector3d::Zero(), gsum = sum;
      Eigen::Matrix3d sq = Eigen::Matrix3d::Zero(), gsq = sq;
      int n = 0, gn = 0;
      for_each_in_window(ix, iy, [&](std::uint32_t i) {
        const Eigen::Vector3d& p = pts[i];
        if (p.z() < lo || p.z() > hi) return;  // pass-through: overhangs fall out
        sum += p;
        sq += p * p.transpose();
        ++n;
        if (ground[i]) {
          gsum += p;
          gsq += p * p.transpose();
          ++gn;
        }
      });
      if (n < c.min_voxel_points) continue;
      // The seed's voxel plane (all points in the voxel) decides the 2D obstacle; the ground's
      // own plane (its ground returns, when enough) gives the slope of the ground there.
      auto fit = [](const Eigen::Vector3d& s1, const Eigen::Matrix3d& s2, int count,
                    Eigen::Vector3d& centroid) {
        centroid = s1 / count;
        const Eigen::Matrix3d cov = s2 / count - centroid * centroid.transpose();
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
        Eigen::Vector3d nrm = eig.eigenvectors().col(0);
        return nrm.z() < 0 ? Eigen::Vector3d(-nrm) : nrm;
      };
      Eigen::Vector3d voxel_centroid, centroid;
      const Eigen::Vector3d voxel_normal = fit(sum, sq, n, voxel_centroid);
      const bool ground_plane = c.ground_plane && gn >= c.min_voxel_points;
      const Eigen::Vector3d normal = ground_plane ? fit(gsum, gsq, gn, centroid) : voxel_normal;
      if (!ground_plane) centroid = voxel_centroid;
      const double rho_voxel = std::acos(std::clamp(voxel_normal.z(), -1.0, 1.0)) / kDeg;
      const double rho = std::acos(std::clamp(normal.z(), -1.0, 1.0)) / kDeg;
      nx[k] = float(normal.x());
      ny[k] = float(normal.y());
      nz[k] = float(normal.z());
      slope[k] = float(rho);
      const bool too_steep = rho_voxel > rho_max || rho > rho_max;
      obst2d[k] = too_steep ? 1.f : 0.f;

      // Step c and claim 5: the cell's own points against the voxel plane; returns between
      // min_obstacle_height and clearance above the local ground are obstacle points.
      const Eigen::Vector2d centre = g.cell_center(ix, iy);
      const double plane_z = std::abs(normal.z()) > 0.05
                                 ? centroid.z() - (normal.x() * (centre.x() - centroid.x()) +
                                                   normal.y() * (centre.y() - centroid.y())) /
                                                      normal.z()
                                 : double(z0);
      const double cell_ground = std::isfinite(low_ground[k]) ? low_ground[k] : plane_z;
      // Step or pit: the height range of the voxel's points about its plane (the cell and its
      // neighbours, as far as the robot reaches).
      double vmin = 0, vmax = 0;
      int vm = 0;
      for_each_in_window(ix, iy, [&](std::uint32_t i) {
        const Eigen::Vector3d& p = pts[i];
        if (p.z() < lo || p.z() > hi || (ground_plane && !ground[i])) return;
        const double d = normal.dot(p - centroid);
        vmin = vm ? std::min(vmin, d) : d;
        vmax = vm ? std::max(vmax, d) : d;
        ++vm;
      });
      double dmin = 0, dmax = 0, dsum = 0;
      int m = 0, raised = 0;
      for (std::uint32_t j = start[k]; j < start[k + 1]; ++j) {
        const Eigen::Vector3d& p = pts[order[j]];
        const double above = p.z() - cell_ground;
        if (!ground[order[j]] && above >= c.robot.min_obstacle_height_m &&
            above <= c.robot.clearance_m)
          ++raised;
        if (p.z() < lo || p.z() > hi) continue;
        const double d = normal.dot(p - centroid);
        dmin = m ? std::min(dmin, d) : d;
        dmax = m ? std::max(dmax, d) : d;
        dsum += std::abs(d);
        ++m;
      }
      if (m == 0) {  // the cell's returns all lie outside its voxel: overhang only, unknown
        slope[k] = nx[k] = ny[k] = nz[k] = obst2d[k] = kNaN;
        continue;
      }
      const double stp = c.voxel_step ? vmax - vmin : dmax - dmin, r = dsum / m;
      step[k] = float(stp);
      rough[k] = float(r);
      rsum[k] = float(dsum);
      elev[k] = float(plane_z);
      const bool projected = c.project_obstacles && raised >= c.min_obstacle_points;
      proj[k] = projected ? 1.f : 0.f;
      const bool blocked = too_steep || stp > c.robot.max_step_m || projected;
      impass[k] = blocked ? 1.f : 0.f;
      tau[k] = blocked ? 0.f
                       : float(std::clamp(1.0 - c.weight_slope * rho / rho_max -
                                              c.weight_roughness * r / r_scale,
                                          0.0, 1.0));
    }
  }
  return map;
}

}  // namespace fieldlidar::terrain
