// Drop-offs seen from above: bands of unseen cells between ground cells of different heights
// (navigate_maps.hpp, mark_drop_bands).

#include <cmath>

#include "fieldlidar/loops/navigate_maps.hpp"

namespace fieldlidar::loops {

namespace {

constexpr int kDropLines[4][2] = {{1, 0}, {0, 1}, {1, 1}, {1, -1}};
constexpr double kDropMaxRayAngle_deg = 30.0;  ///< a line this near the sensor's ray is along it

/// The map's cells as mark_drop_bands reads them.
struct DropField {
  const GridGeometry& area;
  std::span<const float> elevation, points;
  std::span<const std::uint8_t> blocked;
  const AreaGridRules& rules;
  int reach = 0;  ///< cells along a line to look for ground

  bool unseen(std::size_t i) const { return points[i] <= 0.f && !std::isfinite(elevation[i]); }

  /// The first ground cell from (ix, iy) along (dx, dy) within `reach` steps, crossing only
  /// unseen cells: its step count (0: none) and elevation.
  int ground_along(int ix, int iy, int dx, int dy, float& z) const {
    for (int k = 1; k <= reach; ++k) {
      const int x = ix + k * dx, y = iy + k * dy;
      if (!area.contains(x, y)) return 0;
      const std::size_t j = area.linear_index(x, y);
      if (std::isfinite(elevation[j])) {
        z = elevation[j];
        return k;
      }
      if (!unseen(j)) return 0;
    }
    return 0;
  }

  double range(int ix, int iy) const {
    return (area.cell_center(ix, iy) - rules.sensor_xy_m).norm();
  }

  /// The unseen cell (ix, iy) lies in a drop along `line` (see mark_drop_bands).
  bool drop_on_line(int ix, int iy, const int (&line)[2]) const {
    float za = 0, zb = 0;
    const int a = ground_along(ix, iy, line[0], line[1], za);
    const int b = a ? ground_along(ix, iy, -line[0], -line[1], zb) : 0;
    if (b == 0) return false;
    const double apart = (a + b) * area.resolution_m * std::hypot(line[0], line[1]);
    const double drop = std::abs(za - zb);
    if (apart > rules.drop_band_max_m + 1e-9 || !(drop > rules.drop_min_m) ||
        !(drop > std::tan(rules.drop_min_slope_deg * M_PI / 180.0) * apart))
      return false;
    const int k_high = za > zb ? a : -b, k_low = za > zb ? -b : a;
    const int hx = ix + k_high * line[0], hy = iy + k_high * line[1];
    const double z_high = std::max(za, zb), high_d = range(hx, hy);
    // Looked at over the higher side: a face turned to the sensor shows gaps between rings.
    if (range(ix + k_low * line[0], iy + k_low * line[1]) - high_d < 0.5 * area.resolution_m)
      return false;
    // Ground the robot could stand on, not a rock's top kept as ground (its own shadow).
    if (blocked[area.linear_index(hx, hy)]) return false;
    // An edge the robot stands above, not a terrace's far side seen from below it.
    if (z_high > rules.sensor_z_m - rules.sensor_height_m + rules.drop_min_m +
                     rules.drop_rise_per_m * high_d)
      return false;
    // Steep enough to hide under the ray that grazes the higher side.
    const double ray = (rules.sensor_z_m - z_high) / std::max(high_d, area.resolution_m);
    return drop / apart > rules.drop_ray_share * ray;
  }
};

}  // namespace

void mark_drop_bands(const GridGeometry& area, std::span<const float> elevation,
                     std::span<const float> points, std::span<const std::uint8_t> blocked,
                     const AreaGridRules& rules, std::span<std::uint8_t> marks) {
  const double cm = area.resolution_m;
  const DropField f{area,    elevation, points,
                    blocked, rules,     int(std::floor(rules.drop_band_max_m / cm + 1e-9))};
  for (std::size_t i = 0; i < marks.size(); ++i)
    if (marks[i] && !f.unseen(i)) marks[i] = 0;
  if (f.reach < 2 || !(rules.drop_radius_m > rules.blind_radius_m)) return;
  const double min_cos = std::cos(kDropMaxRayAngle_deg * M_PI / 180.0);
  const int r = int(std::ceil(rules.drop_radius_m / cm));
  const Eigen::Vector2d c = (rules.sensor_xy_m - area.origin_m) / cm;
  const int cx = int(std::floor(c.x())), cy = int(std::floor(c.y()));
  for (int iy = std::max(0, cy - r); iy <= std::min(area.height - 1, cy + r); ++iy)
    for (int ix = std::max(0, cx - r); ix <= std::min(area.width - 1, cx + r); ++ix) {
      const std::size_t i = area.linear_index(ix, iy);
      if (marks[i] == kDropBandMark || !f.unseen(i)) continue;
      const double d = f.range(ix, iy);
      if (d > rules.drop_radius_m || d < 1e-9) continue;
      const Eigen::Vector2d ray = (area.cell_center(ix, iy) - rules.sensor_xy_m) / d;
      if (d < blind_range_m(rules, ray)) continue;
      for (const auto& line : kDropLines)
        if (std::abs(ray.dot(Eigen::Vector2d(line[0], line[1]).normalized())) >= min_cos &&
            f.drop_on_line(ix, iy, line)) {
          marks[i] = kDropBandMark;
          break;
        }
    }
}

}  // namespace fieldlidar::loops
