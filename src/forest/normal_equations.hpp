#pragma once
// Sums of outer products over many residuals or points (Gauss-Newton normal matrices H = sum J
// J^T, scatter matrices): symmetric, so each term adds to the lower half only (n (n + 1) / 2
// products, not n^2), and the upper half is copied once before the solve.

#include <Eigen/Core>

namespace fieldlidar::forest {

/// H(r, c) += J(r) J(c) for r >= c.
template <int N>
inline void add_outer_lower(Eigen::Matrix<double, N, N>& H, const Eigen::Matrix<double, N, 1>& J) {
  for (int c = 0; c < N; ++c)
    for (int r = c; r < N; ++r) H(r, c) += J(r) * J(c);
}

/// The upper half of H from its lower half.
template <int N>
inline void mirror_lower(Eigen::Matrix<double, N, N>& H) {
  for (int c = 1; c < N; ++c)
    for (int r = 0; r < c; ++r) H(r, c) = H(c, r);
}

}  // namespace fieldlidar::forest
