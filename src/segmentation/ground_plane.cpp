#include "ground_plane.hpp"

#include "polar_grid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include <Eigen/Dense>

#include "fieldlidar/segmentation/ground.hpp"

namespace fieldlidar::segmentation {

NearGroundPlane fit_near_ground_plane(const PointCloud& cloud, double near_range_m,
                                      double max_tilt_rad, double inner_m) {
  constexpr int kSectors = 36;
  const int rings = std::max(1, int(std::ceil(near_range_m - inner_m)));
  struct Low {
    float x = 0, y = 0, z = std::numeric_limits<float>::max();
  };
  std::vector<Low> lowest(std::size_t(kSectors) * rings);
  const float inner2 = float(inner_m * inner_m), near2 = float(near_range_m * near_range_m);
  const float sectors_per_rad = float(kSectors / (2 * std::numbers::pi));
  for (const Point& p : cloud.points) {
    if (!(p.z < 0.f) || !valid_point(p)) continue;
    const float r2 = p.x * p.x + p.y * p.y;
    if (r2 < inner2 || r2 >= near2) continue;
    const int ring = std::min(rings - 1, int(std::sqrt(r2) - float(inner_m)));
    const float az = fast_atan2(p.y, p.x) + float(std::numbers::pi);
    const int sector = std::clamp(int(az * sectors_per_rad), 0, kSectors - 1);
    Low& low = lowest[std::size_t(sector) * rings + ring];
    if (p.z < low.z) low = {p.x, p.y, p.z};
  }
  std::vector<Eigen::Vector3f> cells;
  for (const Low& l : lowest)
    if (l.z != std::numeric_limits<float>::max()) cells.emplace_back(l.x, l.y, l.z);
  return fit_plane_to_lows(cells, max_tilt_rad);
}

NearGroundPlane fit_plane_to_lows(std::span<const Eigen::Vector3f> cells, double max_tilt_rad) {
  NearGroundPlane plane;
  if (cells.size() < 8) return plane;
  std::vector<float> z(cells.size());
  for (std::size_t k = 0; k < cells.size(); ++k) z[k] = cells[k].z();
  std::nth_element(z.begin(), z.begin() + z.size() / 2, z.end());
  plane.c = z[z.size() / 2];
  // Trim and refit with a shrinking band; the first pass starts from the level median plane.
  const double max_grad = std::tan(max_tilt_rad);
  for (double band : {0.6, 0.3, 0.15, 0.1}) {
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
    std::size_t n = 0;
    for (const Eigen::Vector3f& l : cells) {
      if (std::abs(l.z() - plane.height_at(l.x(), l.y())) > band) continue;
      const Eigen::Vector3d v(l.x(), l.y(), 1.0);
      A.noalias() += v * v.transpose();
      rhs += v * double(l.z());
      ++n;
    }
    if (n < 6) break;
    const Eigen::Vector3d sol = A.ldlt().solve(rhs);
    if (!sol.allFinite()) break;
    const double grad = std::hypot(sol(0), sol(1));
    const double s = grad > max_grad ? max_grad / grad : 1.0;
    plane.a = sol(0) * s;
    plane.b = sol(1) * s;
    plane.c = sol(2);
    plane.support = n;
    plane.found = true;
  }
  return plane;
}

double estimate_sensor_height(const PointCloud& cloud, double near_range_m, double fallback_m) {
  const NearGroundPlane plane = fit_near_ground_plane(cloud, near_range_m);
  if (!plane.found) return fallback_m;
  // Distance from the sensor origin to the plane a x + b y - z + c = 0.
  return -plane.c / std::sqrt(1.0 + plane.a * plane.a + plane.b * plane.b);
}

}  // namespace fieldlidar::segmentation
