#pragma once
/// \file The normal of a ground plane fitted to returns (PCA), with the plane's tilt across a
/// line of returns left unmeasured: one ring crossing a cell lies along a line, its range noise
/// along the beam, and PCA on it returns the plane through the ring and the beam, tilted by the
/// beam's depression whatever the ground's slope (a VLP-32C's lowest ring, at -25 deg, read
/// level ground as 15-27 deg steep).

#include <Eigen/Core>
#include <Eigen/Eigenvalues>

namespace fieldlidar::terrain::detail {

/// Unit normal (z >= 0) of the plane of returns whose covariance `eig` decomposed. When they
/// spread (standard deviation) less than `min_spread_m` across their main direction they lie
/// along a line: the least-tilted plane through that line (its slope the line's own); when less
/// than that along it too, the level plane. min_spread_m = 0: plain PCA.
Eigen::Vector3d plane_normal(const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>& eig,
                             double min_spread_m);

}  // namespace fieldlidar::terrain::detail
