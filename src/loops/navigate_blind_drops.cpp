// Drop-offs hidden in the blind disk: ground seen beyond it that does not lead back up to the
// ground the robot stands on (navigate_maps.hpp, mark_blind_drops).

#include <algorithm>
#include <cmath>
#include <vector>

#include "fieldlidar/loops/navigate_maps.hpp"

namespace fieldlidar::loops {

namespace {

/// Where a ray from the sensor first meets ground, and what it crossed on the way.
struct RayGround {
  std::vector<std::size_t> unseen;  ///< cells without a return nor ground, nearest first
  double d1 = 0, z1 = 0;            ///< the first ground cell: range (m), elevation (m)
  bool found = false;
  bool sloped = false;  ///< a second ground cell far enough beyond the first for a slope
  double slope = 0;     ///< the ground's rise per metre beyond the first ground cell
};

}  // namespace

void mark_blind_drops(const GridGeometry& area, std::span<const float> elevation,
                      std::span<const float> points, const AreaGridRules& rules,
                      std::span<std::uint8_t> marks) {
  if (!(rules.blind_drop_clear_m > 0) || !(rules.blind_radius_m > rules.blind_drop_clear_m)) return;
  const double cm = area.resolution_m, step = 0.5 * cm;
  const double reach = rules.blind_radius_m + rules.blind_drop_reach_m;
  const double z_robot = rules.sensor_z_m - rules.sensor_height_m;
  const Eigen::Vector3d n = rules.ground_normal.normalized();
  if (!(n.z() > 0.5)) return;  // a robot on its side knows no ground plane
  const Eigen::Vector2d grad(-n.x() / n.z(), -n.y() / n.z());  // the robot's plane's rise per m
  const Eigen::Vector3d up = rules.sensor_up.normalized();
  const double lowest = std::atan2(rules.sensor_height_m, rules.blind_radius_m);
  const double max_rise = std::tan(rules.max_slope_deg * M_PI / 180.0);
  const int directions = std::max(16, int(std::ceil(2.0 * M_PI * reach / step)));

  auto march = [&](const Eigen::Vector2d& u) {
    RayGround g;
    long last = -1;
    for (double r = std::max(step, rules.blind_drop_clear_m - cm);
         r <= reach + rules.blind_drop_slope_run_m; r += step) {
      const auto c = area.cell_of(rules.sensor_xy_m + r * u);
      if (!c) return RayGround{};
      const std::size_t i = area.linear_index(c->x(), c->y());
      if (long(i) == last) continue;
      last = long(i);
      const double d = (area.cell_center(c->x(), c->y()) - rules.sensor_xy_m).norm();
      if (std::isfinite(elevation[i])) {
        if (!g.found) {
          if (d > reach) return RayGround{};
          g.found = true;
          g.d1 = d;
          g.z1 = elevation[i];
        } else if (d - g.d1 >= rules.blind_drop_slope_run_m - cm) {
          g.sloped = true;
          g.slope = std::clamp((elevation[i] - g.z1) / (d - g.d1), -max_rise, max_rise);
          return g;
        }
      } else if (!g.found) {
        if (points[i] > 0.f) return RayGround{};  // a return without ground: not a shadow
        if (d >= rules.blind_drop_clear_m) g.unseen.push_back(i);
      }
    }
    return g;
  };

  // The first ground is the end of a shadow: where the lowest beam meets it from here, or from
  // an earlier sweep's sensor behind the robot on nearly the same line (level there).
  const double tol = rules.blind_drop_shadow_tolerance_m, min_cos = std::cos(M_PI / 6.0);
  auto shadow_end = [&](const RayGround& g, const Eigen::Vector2d& u) {
    const double down = lowest + std::atan2(up.head<2>().dot(u), up.z());
    if (down > 0 && g.d1 >= (rules.sensor_z_m - g.z1) / std::tan(down) - tol) return true;
    const Eigen::Vector2d ground = rules.sensor_xy_m + g.d1 * u;
    for (const auto& e : rules.earlier_sensors_m) {
      const Eigen::Vector2d v = ground - e.head<2>();
      const double d = v.norm();
      if (d > g.d1 && v.dot(u) >= min_cos * d && d >= (e.z() - g.z1) / std::tan(lowest) - tol)
        return true;
    }
    return false;
  };

  for (int k = 0; k < directions; ++k) {
    const double a = 2.0 * M_PI * k / directions;
    const Eigen::Vector2d u(std::cos(a), std::sin(a));
    const RayGround g = march(u);
    if (!g.found || g.unseen.empty()) continue;
    // The shadow's end: the sensor's lowest beam meets that ground there, not nearer (ground
    // nearer was seen from another pose, and the band before it is no shadow of this one).
    if (!shadow_end(g, u)) continue;
    // Lower than the robot's own ground plane carried out to it, by more than a step ...
    const double plane = z_robot + grad.dot(g.d1 * u);
    if (!(plane - g.z1 > rules.drop_min_m + rules.drop_rise_per_m * g.d1)) continue;
    // ... and the ground beyond, followed back to the robot, passes below it by more than a
    // step: a slope falling away from a crest leads back up to the robot's level, a drop's foot
    // does not (ground rising beyond is followed back level: no rise leads down to a hollow).
    if (g.sloped && !(z_robot - (g.z1 - std::min(g.slope, 0.0) * g.d1) > rules.drop_min_m))
      continue;
    for (std::size_t i : g.unseen)
      if (!marks[i]) marks[i] = kBlindDropMark;
  }
}

}  // namespace fieldlidar::loops
