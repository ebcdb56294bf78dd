// Step 3 of seed 003: bounded circle fits on partial arcs, and the axis through their centres.
#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Dense>

#include "fieldlidar/forest/trunks.hpp"
#include "normal_equations.hpp"

namespace fieldlidar::forest {

Circle fit_circle(std::span<const Eigen::Vector2d> points, double min_radius_m, double max_radius_m,
                  int iterations) {
  Circle c;
  const std::size_t n = points.size();
  if (n < 3) return c;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& p : points) mean += p;
  mean /= double(n);
  // Kasa: x^2 + y^2 + D x + E y + F = 0, in coordinates centred on the mean.
  Eigen::MatrixXd A(n, 3);
  Eigen::VectorXd b(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d q = points[i] - mean;
    A.row(i) << q.x(), q.y(), 1.0;
    b(i) = -q.squaredNorm();
  }
  const Eigen::Vector3d s = A.colPivHouseholderQr().solve(b);
  Eigen::Vector2d center = mean + Eigen::Vector2d(-s(0) / 2, -s(1) / 2);
  double r2 = s(0) * s(0) / 4 + s(1) * s(1) / 4 - s(2);
  double r = (std::isfinite(r2) && r2 > 0) ? std::sqrt(r2) : min_radius_m;
  if (!center.allFinite() || r > 10 * max_radius_m) {
    // Nearly straight: start behind the points, away from the sensor side is unknown, so use
    // the mean shifted by the smallest radius along the normal of the points' spread.
    Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
    for (const auto& p : points) cov += (p - mean) * (p - mean).transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(cov);
    Eigen::Vector2d nrm = es.eigenvectors().col(0);
    if (nrm.dot(mean) < 0) nrm = -nrm;  // away from the origin (the sensor)
    r = min_radius_m;
    center = mean + nrm * r;
  }
  r = std::clamp(r, min_radius_m, max_radius_m);
  // Gauss-Newton on d_i = |p_i - c| - r with r clamped to its bounds after each step.
  for (int it = 0; it < iterations; ++it) {
    Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
    Eigen::Vector3d g = Eigen::Vector3d::Zero();
    for (const auto& p : points) {
      const Eigen::Vector2d d = p - center;
      const double len = std::max(d.norm(), 1e-9);
      const double res = len - r;
      const Eigen::Vector3d J(-d.x() / len, -d.y() / len, -1.0);
      add_outer_lower(H, J);
      g += J * res;
    }
    mirror_lower(H);
    H.diagonal().array() += 1e-9;
    const Eigen::Vector3d step = H.ldlt().solve(-g);
    if (!step.allFinite()) break;
    center += step.head<2>();
    r = std::clamp(r + step(2), min_radius_m, max_radius_m);
    if (step.norm() < 1e-7) break;
  }
  double ss = 0;
  for (const auto& p : points) ss += std::pow((p - center).norm() - r, 2);
  c.center = center;
  c.radius_m = r;
  c.residual_m = std::sqrt(ss / double(n));
  c.ok = center.allFinite() && std::isfinite(r);
  return c;
}

double arc_coverage_deg(std::span<const Eigen::Vector2d> points, const Eigen::Vector2d& center) {
  if (points.size() < 2) return 0.0;
  std::vector<double> a;
  a.reserve(points.size());
  for (const auto& p : points) a.push_back(std::atan2(p.y() - center.y(), p.x() - center.x()));
  std::sort(a.begin(), a.end());
  double widest = a.front() + 2 * std::numbers::pi - a.back();
  for (std::size_t i = 1; i < a.size(); ++i) widest = std::max(widest, a[i] - a[i - 1]);
  return (2 * std::numbers::pi - widest) * 180.0 / std::numbers::pi;
}

Axis fit_axis(std::span<const Eigen::Vector3d> centres, double reject_m, int iterations) {
  Axis axis;
  std::vector<std::size_t> in(centres.size());
  for (std::size_t i = 0; i < in.size(); ++i) in[i] = i;
  for (int it = 0; it <= iterations; ++it) {
    if (in.size() < 2) return axis;
    // x = x0 + a (z - zm), y = y0 + b (z - zm)
    double zm = 0;
    for (auto i : in) zm += centres[i].z();
    zm /= double(in.size());
    double szz = 0, sx = 0, sy = 0, sxz = 0, syz = 0;
    for (auto i : in) {
      const double dz = centres[i].z() - zm;
      szz += dz * dz;
      sx += centres[i].x();
      sy += centres[i].y();
      sxz += centres[i].x() * dz;
      syz += centres[i].y() * dz;
    }
    const double n = double(in.size());
    const double a = szz > 1e-6 ? sxz / szz : 0.0, b = szz > 1e-6 ? syz / szz : 0.0;
    axis.point = Eigen::Vector3d(sx / n, sy / n, zm);
    axis.direction = Eigen::Vector3d(a, b, 1.0).normalized();
    axis.inliers = in;
    axis.ok = true;
    // Distances of all centres; keep those within max(reject, 2.5 sigma of the inliers).
    std::vector<double> d(centres.size());
    double ss = 0;
    for (std::size_t i = 0; i < centres.size(); ++i) {
      const double dz = centres[i].z() - zm;
      d[i] =
          (centres[i].head<2>() - Eigen::Vector2d(axis.point.x() + a * dz, axis.point.y() + b * dz))
              .norm();
    }
    for (auto i : in) ss += d[i] * d[i];
    const double thr = std::max(reject_m, 2.5 * std::sqrt(ss / n));
    std::vector<std::size_t> next;
    for (std::size_t i = 0; i < centres.size(); ++i)
      if (d[i] <= thr) next.push_back(i);
    if (next == in) break;
    in = std::move(next);
  }
  return axis;
}

}  // namespace fieldlidar::forest
