// Smallest eigenpair of a symmetric positive semi-definite 3x3 matrix without trigonometry.

#include "smallest_eigen.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

namespace fieldlidar::segmentation::detail {

SmallestEigen smallest_eigen(const Eigen::Matrix3d& c) {
  const double c1 = c.trace();
  const double c2 = c(0, 0) * c(1, 1) - c(0, 1) * c(0, 1) + c(0, 0) * c(2, 2) - c(0, 2) * c(0, 2) +
                    c(1, 1) * c(2, 2) - c(1, 2) * c(1, 2);
  const double c3 = c.determinant();
  SmallestEigen out;
  // p(l) = det(C - l I) = -l^3 + c1 l^2 - c2 l + c3, convex left of its smallest root.
  double l = 0;
  for (int it = 0; it < 100 && c3 > 0; ++it) {
    const double p = ((-l + c1) * l - c2) * l + c3;
    const double dp = (-3 * l + 2 * c1) * l - c2;
    if (!(dp < 0)) break;
    const double step = p / dp;
    l -= step;
    if (std::abs(step) <= 1e-15 * c1) break;
  }
  out.value = std::max(l, 0.0);
  const double s = c1 - out.value, q = c2 - out.value * s;  // l2 + l3 and l2 * l3
  out.second_value = std::max(0.0, 0.5 * (s - std::sqrt(std::max(0.0, s * s - 4 * q))));
  const Eigen::Matrix3d m = c - out.value * Eigen::Matrix3d::Identity();
  const Eigen::Vector3d v01 = m.row(0).cross(m.row(1)), v02 = m.row(0).cross(m.row(2)),
                        v12 = m.row(1).cross(m.row(2));
  const double n01 = v01.squaredNorm(), n02 = v02.squaredNorm(), n12 = v12.squaredNorm();
  const double best = std::max({n01, n02, n12});
  if (best > 1e-30 * c1 * c1 * c1 * c1) {
    out.vector = (n01 == best ? v01 : n02 == best ? v02 : v12) / std::sqrt(best);
  } else {  // repeated smallest eigenvalue: any vector of its eigenspace will do
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
    es.computeDirect(c);
    out.vector = es.eigenvectors().col(0);
  }
  return out;
}

}  // namespace fieldlidar::segmentation::detail
