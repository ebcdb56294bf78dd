#include "fieldlidar/core/rotate_points.hpp"

namespace fieldlidar {

void rotate_points(PointCloud& cloud, const Eigen::Matrix3f& R) {
  if (R == Eigen::Matrix3f::Identity()) return;  // a level sweep: nothing to turn
  for (Point& p : cloud.points) {
    if (!p.is_valid()) continue;
    const Eigen::Vector3f q = R * p.xyz();
    p.x = q.x();
    p.y = q.y();
    p.z = q.z();
  }
}

}  // namespace fieldlidar
