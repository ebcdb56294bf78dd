// Planar path measures: length, Menger curvature, turning, direction changes.

#include "fieldlidar/planning/pose2.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace fieldlidar::planning {

double path_length_m(const Path& path) {
  double length = 0.0;
  for (std::size_t i = 1; i < path.size(); ++i)
    length += std::hypot(path[i].pose.x_m - path[i - 1].pose.x_m,
                         path[i].pose.y_m - path[i - 1].pose.y_m);
  return length;
}

double menger_curvature(const Path& path, std::size_t i) {
  if (i == 0 || i + 1 >= path.size()) return 0.0;
  // A cusp (change of direction) is a stop, not a bend.
  if (path[i].reverse != path[i + 1].reverse) return 0.0;
  const Pose2& a = path[i - 1].pose;
  const Pose2& b = path[i].pose;
  const Pose2& c = path[i + 1].pose;
  const double abx = b.x_m - a.x_m, aby = b.y_m - a.y_m;
  const double bcx = c.x_m - b.x_m, bcy = c.y_m - b.y_m;
  const double acx = c.x_m - a.x_m, acy = c.y_m - a.y_m;
  const double ab = std::hypot(abx, aby), bc = std::hypot(bcx, bcy), ac = std::hypot(acx, acy);
  if (ab < 1e-9 || bc < 1e-9 || ac < 1e-9) return 0.0;
  const double cross = std::abs(abx * acy - aby * acx);  // twice the triangle's area
  return 2.0 * cross / (ab * bc * ac);
}

double max_curvature(const Path& path) {
  double k = 0.0;
  for (std::size_t i = 1; i + 1 < path.size(); ++i) k = std::max(k, menger_curvature(path, i));
  return k;
}

double total_turning_rad(const Path& path) {
  double turning = 0.0;
  for (std::size_t i = 1; i < path.size(); ++i)
    turning += std::abs(wrap_angle(path[i].pose.yaw_rad - path[i - 1].pose.yaw_rad));
  return turning;
}

int direction_changes(const Path& path) {
  int n = 0;
  for (std::size_t i = 1; i < path.size(); ++i) n += path[i].reverse != path[i - 1].reverse;
  return n;
}

}  // namespace fieldlidar::planning
