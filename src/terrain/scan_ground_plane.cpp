/// The ground under an obstacle return by the plane of the scan's ground returns around it: on a
/// hill's flank a return in the upper part of a 0.5 m cell (or in a cell whose own returns the
/// ground segmentation left out) stands above the lowest ground near it by the slope alone, not
/// by an object.
#include <cmath>
#include <numbers>

#include <Eigen/Eigenvalues>

#include "fused_cell.hpp"

namespace fieldlidar::terrain::detail {

double scan_ground_plane_z(std::span<ScanCell> local, int x, int y, int w, int h, double dx,
                           double dy, const FusionConfig& config) {
  ScanCell& s = local[std::size_t(y) * w + x];
  if (!s.plane_done) {
    s.plane_done = true;
    const double cm = config.layers.cell_m;
    PlaneSums sums;
    for (int ny = -1; ny <= 1; ++ny)
      for (int nx = -1; nx <= 1; ++nx)
        if (x + nx >= 0 && y + ny >= 0 && x + nx < w && y + ny < h)
          sums.add_shifted(local[std::size_t(y + ny) * w + x + nx].scan_ground,
                           {nx * cm, ny * cm, 0.0});
    if (sums.n < config.layers.min_voxel_points) return std::numeric_limits<double>::quiet_NaN();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
    eig.computeDirect(sums.covariance());
    const Eigen::Vector3d n = eig.eigenvectors().col(0);
    // Returns along one line (a single ring) give no plane: the two smallest spreads alike.
    const Eigen::Vector3d ev = eig.eigenvalues();
    constexpr double kDeg = std::numbers::pi / 180.0;
    if (!(ev[1] > 4.0 * ev[0]) ||
        std::abs(n.z()) < std::cos(config.layers.robot.max_slope_deg * kDeg))
      return std::numeric_limits<double>::quiet_NaN();
    const Eigen::Vector3d m = sums.mean();
    s.plane_dzdx = float(-n.x() / n.z());
    s.plane_dzdy = float(-n.y() / n.z());
    s.plane_z = float(m.z() - s.plane_dzdx * m.x() - s.plane_dzdy * m.y());
  }
  return double(s.plane_z) + s.plane_dzdx * dx + s.plane_dzdy * dy;
}

}  // namespace fieldlidar::terrain::detail
