#pragma once
// Small helpers shared by the simulator tests.

#include <Eigen/Dense>

#include "fieldlidar/sim/scene.hpp"

namespace fieldlidar::sim::test {

/// A custom scene: flat ground at height `z_m` over [-r, r]^2.
inline Scene flat_scene(double z_m, double half_size_m = 40.0) {
  return Scene(SceneKind::kCustom,
               HeightField({-half_size_m, -half_size_m}, {half_size_m, half_size_m}, 1.0,
                           [z_m](double, double) { return z_m; }));
}

/// Least-squares circle (Kasa fit) through 2D points: centre and radius.
inline std::pair<Eigen::Vector2d, double> fit_circle(const std::vector<Eigen::Vector2d>& pts) {
  Eigen::MatrixXd A(pts.size(), 3);
  Eigen::VectorXd b(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    A(i, 0) = 2 * pts[i].x();
    A(i, 1) = 2 * pts[i].y();
    A(i, 2) = 1;
    b(i) = pts[i].squaredNorm();
  }
  const Eigen::Vector3d s = A.colPivHouseholderQr().solve(b);
  const Eigen::Vector2d c(s(0), s(1));
  return {c, std::sqrt(s(2) + c.squaredNorm())};
}

}  // namespace fieldlidar::sim::test
