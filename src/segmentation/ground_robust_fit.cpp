// The plane of one polar cell of the robust ground: a PCA of its low points, and the statistics
// of a cell that holds a single scan line.

#include <algorithm>
#include <cmath>

#include "ground_robust_cells.hpp"
#include "smallest_eigen.hpp"

namespace fieldlidar::segmentation::detail {

LineStats line_stats(std::span<const CellPoint> members, const float* rho, float band) {
  double sum = 0;
  int n = 0;
  for (std::size_t k = 0; k < members.size(); ++k)
    if (members[k].z <= band) {
      sum += rho[k];
      ++n;
    }
  return {float(sum / std::max(1, n)), n == int(members.size())};
}

PlaneFit fit_cell(std::span<const CellPoint> members, float z_min, double seed_band_m,
                  float max_cos, float cx, float cy, CellFit& fit) {
  const float band = z_min + float(seed_band_m);
  // Moments about the lowest return (small numbers, no cancellation): 3 sums, 6 products.
  const CellPoint& o = members.front();
  double sx = 0, sy = 0, sz = 0, xx = 0, xy = 0, xz = 0, yy = 0, yz = 0, zz = 0;
  int n = 0;
  for (const CellPoint& p : members) {
    if (p.z > band) continue;
    const double x = p.x - o.x, y = p.y - o.y, z = p.z - o.z;
    sx += x;
    sy += y;
    sz += z;
    xx += x * x;
    xy += x * y;
    xz += x * z;
    yy += y * y;
    yz += y * z;
    zz += z * z;
    ++n;
  }
  const Eigen::Vector3d local_mean = Eigen::Vector3d(sx, sy, sz) / n;
  const Eigen::Vector3d mean = local_mean + Eigen::Vector3d(o.x, o.y, o.z);
  PlaneFit out;
  if (n >= 4) {
    Eigen::Matrix3d cov;
    cov << xx, xy, xz, xy, yy, yz, xz, yz, zz;
    cov = cov / n - local_mean * local_mean.transpose();
    const SmallestEigen es = smallest_eigen(cov);
    // Points on a single scan line span one direction only: the plane is undetermined, keep it
    // horizontal through their mean.
    if (std::sqrt(es.second_value) > 0.04) {
      Eigen::Vector3d nrm = es.vector;
      if (nrm.z() < 0) nrm = -nrm;
      out.normal = nrm.cast<float>();
      out.flatness = float(std::sqrt(es.value));
      out.upright = out.normal.z() >= max_cos;
    } else {
      out.line_only = true;
    }
  } else {
    out.line_only = true;
  }
  if (!out.upright) out.normal = {0.f, 0.f, 1.f};
  const Eigen::Vector3f& nm = out.normal;
  const float d = float(-nm.cast<double>().dot(mean));  // plane: normal . p + d = 0
  fit.elevation = -(nm.x() * cx + nm.y() * cy + d) / nm.z();
  fit.gx = nm.x() / nm.z();
  fit.gy = nm.y() / nm.z();
  fit.g0 = d / nm.z();
  return out;
}

}  // namespace fieldlidar::segmentation::detail
