// How near the footprint comes to the scene's obstacles themselves: the truth marks a whole 0.5 m
// cell impassable when a rock's disc reaches into it, so a footprint on such a cell may still
// stand clear of the rock; the gap to the disc tells a brushed cell from a contact.

#include <algorithm>
#include <cmath>
#include <limits>

#include "navigate_loop.hpp"

namespace fieldlidar::loops::detail {

double Loop::obstacle_gap_m(const Pose2& pose) const {
  const double a = 0.5 * robot_.length_m, b = 0.5 * robot_.width_m;
  const double cs = std::cos(pose.yaw_rad), sn = std::sin(pose.yaw_rad);
  double gap = std::numeric_limits<double>::infinity();
  for (const auto& o : scene_.obstacles()) {
    // The obstacles Scene::terrain_truth counts.
    if (!o.blocks(robot_.clearance_m, robot_.min_obstacle_height_m)) continue;
    const Eigen::Vector2d d = o.center_m - Eigen::Vector2d(pose.x_m, pose.y_m);
    const Eigen::Vector2d local(cs * d.x() + sn * d.y(), -sn * d.x() + cs * d.y());
    const Eigen::Vector2d edge(std::clamp(local.x(), -a, a), std::clamp(local.y(), -b, b));
    // Outside: the distance from the rectangle to the disc; inside: minus how deep it reaches.
    const double g =
        edge == local ? -(o.radius_m + std::min(a - std::abs(local.x()), b - std::abs(local.y())))
                      : (local - edge).norm() - o.radius_m;
    gap = std::min(gap, g);
  }
  return gap;
}

}  // namespace fieldlidar::loops::detail
