#pragma once
// Geometry checks shared by the stream decoder tests: azimuth coverage, plane fits.

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include <Eigen/Dense>

#include "fieldlidar/core/point_cloud.hpp"

namespace fieldlidar::test {

/// Degrees of azimuth (1-degree bins) that hold at least one valid point.
inline double azimuth_coverage_deg(const PointCloud& cloud) {
  std::vector<bool> bins(360, false);
  for (const auto& p : cloud.points)
    if (p.is_valid()) {
      double a = std::atan2(p.y, p.x) * 180.0 / std::numbers::pi;
      if (a < 0) a += 360;
      bins[std::size_t(a) % 360] = true;
    }
  double n = 0;
  for (bool b : bins) n += b;
  return n;
}

struct PlaneFit {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double rms_m = 0;  ///< residual RMS of the inliers
  std::size_t inliers = 0;
  std::size_t candidates = 0;
};

/// Least-squares plane with iterative rejection of points farther than max(3 rms, 3 cm).
inline PlaneFit fit_plane(const std::vector<Eigen::Vector3d>& pts) {
  PlaneFit fit;
  fit.candidates = pts.size();
  std::vector<Eigen::Vector3d> cur = pts;
  for (int iter = 0; iter < 8 && cur.size() >= 3; ++iter) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (const auto& p : cur) c += p;
    c /= double(cur.size());
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (const auto& p : cur) cov += (p - c) * (p - c).transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
    fit.normal = es.eigenvectors().col(0);
    double ss = 0;
    for (const auto& p : cur) ss += std::pow(fit.normal.dot(p - c), 2);
    fit.rms_m = std::sqrt(ss / double(cur.size()));
    fit.inliers = cur.size();
    const double gate = std::max(3 * fit.rms_m, 0.03);
    std::vector<Eigen::Vector3d> next;
    for (const auto& p : pts)
      if (std::abs(fit.normal.dot(p - c)) < gate) next.push_back(p);
    if (next.size() == cur.size()) break;
    cur = std::move(next);
  }
  return fit;
}

/// Valid points of rings [ring_lo, ring_hi] closer than max_range_m (horizontal).
inline std::vector<Eigen::Vector3d> low_ring_points(const PointCloud& cloud, int ring_lo,
                                                    int ring_hi, double max_range_m) {
  std::vector<Eigen::Vector3d> out;
  for (const auto& p : cloud.points)
    if (p.is_valid() && p.ring >= ring_lo && p.ring <= ring_hi &&
        std::hypot(p.x, p.y) < max_range_m)
      out.emplace_back(p.x, p.y, p.z);
  return out;
}

/// Plane-fit RMS (m) of every azimuth sector of `sector_deg` over rings [ring_lo, ring_hi] within
/// max_range_m, for sectors holding at least min_points; sorted ascending.
inline std::vector<double> sector_plane_rms(const PointCloud& cloud, int ring_lo, int ring_hi,
                                            double max_range_m, double sector_deg,
                                            std::size_t min_points = 30) {
  const int sectors = int(360.0 / sector_deg);
  std::vector<std::vector<Eigen::Vector3d>> bins(static_cast<std::size_t>(sectors));
  for (const auto& p : low_ring_points(cloud, ring_lo, ring_hi, max_range_m)) {
    double a = std::atan2(p.y(), p.x()) * 180.0 / std::numbers::pi;
    if (a < 0) a += 360;
    bins[std::size_t(int(a / sector_deg) % sectors)].push_back(p);
  }
  std::vector<double> out;
  for (const auto& b : bins) {
    if (b.size() < min_points) continue;
    const auto fit = fit_plane(b);
    if (fit.inliers * 10 >= b.size() * 8) out.push_back(fit.rms_m);  // mostly one surface
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace fieldlidar::test
