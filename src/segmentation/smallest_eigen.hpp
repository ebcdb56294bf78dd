#pragma once
// The smallest eigenpair of a symmetric positive semi-definite 3x3 matrix (a covariance), without
// trigonometry. Internal to segmentation/.

#include <Eigen/Core>

namespace fieldlidar::segmentation::detail {

struct SmallestEigen {
  double value = 0, second_value = 0;                 ///< the two smallest eigenvalues, >= 0
  Eigen::Vector3d vector = Eigen::Vector3d::UnitZ();  ///< unit eigenvector of `value`
};

/// Newton's method on the characteristic polynomial from 0 climbs monotonically to the smallest
/// root, the second one follows from the other coefficients, the vector from cross products of
/// (C - l1 I)'s rows (Eigen's closed form spends most of its time in acos/cos/sin).
SmallestEigen smallest_eigen(const Eigen::Matrix3d& c);

}  // namespace fieldlidar::segmentation::detail
