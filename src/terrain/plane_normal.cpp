#include "plane_normal.hpp"

#include <algorithm>
#include <cmath>

namespace fieldlidar::terrain::detail {

Eigen::Vector3d plane_normal(const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>& eig,
                             double min_spread_m) {
  const Eigen::Vector3d& ev = eig.eigenvalues();  // ascending
  const double min_var = min_spread_m * min_spread_m;
  Eigen::Vector3d n = eig.eigenvectors().col(0);
  if (min_spread_m > 0 && std::max(0.0, ev[1]) < min_var) {
    if (std::max(0.0, ev[2]) < min_var) return Eigen::Vector3d::UnitZ();  // a blob: no slope
    // Of the planes holding the line's direction d, the one whose normal is nearest the
    // vertical: z minus its part along d.
    const Eigen::Vector3d d = eig.eigenvectors().col(2);
    const Eigen::Vector3d up = Eigen::Vector3d::UnitZ() - d.z() * d;
    if (up.norm() > 1e-6) n = up.normalized();  // else a vertical line: PCA's plane holds it
  }
  return n.z() < 0 ? Eigen::Vector3d(-n) : n;
}

}  // namespace fieldlidar::terrain::detail
