// A straight cylinder through stem points: Gauss-Newton in the frame of an initial axis, with
// returns far off the surface (twigs, branches, mixed edge returns) trimmed between rounds.
#include <algorithm>
#include <cmath>

#include <Eigen/Dense>
#include <Eigen/Geometry>

#include "fieldlidar/forest/trunks.hpp"
#include "normal_equations.hpp"

namespace fieldlidar::forest {
namespace {

struct Local {
  Eigen::Vector2d c = Eigen::Vector2d::Zero();  // axis at local height 0
  Eigen::Vector2d s = Eigen::Vector2d::Zero();  // axis slope per metre of local height
  double r = 0.1;
};

// Sum of squared distances of the kept points from the surface of `m`.
double cylinder_cost(std::span<const Eigen::Vector3d> q, const std::vector<char>& keep,
                     const Local& m) {
  double ss = 0;
  for (std::size_t i = 0; i < q.size(); ++i)
    if (keep[i]) ss += std::pow((q[i].head<2>() - m.c - m.s * q[i].z()).norm() - m.r, 2);
  return ss;
}

// Gauss-Newton on |q_xy - c - s q_z| - r over the kept points; s held at 0 unless fit_slope.
// With `backtrack`, a step that does not lower the cost is halved until it does (at most 12
// times, then the fit stops where it is).
void cylinder_gauss_newton(std::span<const Eigen::Vector3d> q, const std::vector<char>& keep,
                           Local& m, bool fit_slope, double min_r, double max_r, bool backtrack) {
  double current = backtrack ? cylinder_cost(q, keep, m) : 0.0;
  for (int it = 0; it < 15; ++it) {
    Eigen::Matrix<double, 5, 5> H = Eigen::Matrix<double, 5, 5>::Zero();
    Eigen::Matrix<double, 5, 1> g = Eigen::Matrix<double, 5, 1>::Zero();
    for (std::size_t i = 0; i < q.size(); ++i) {
      if (!keep[i]) continue;
      const Eigen::Vector2d w = q[i].head<2>() - m.c - m.s * q[i].z();
      const double len = std::max(w.norm(), 1e-9);
      const Eigen::Vector2d e = w / len;
      Eigen::Matrix<double, 5, 1> J;
      J << -e.x(), -e.y(), -e.x() * q[i].z(), -e.y() * q[i].z(), -1.0;
      add_outer_lower(H, J);
      g += J * (len - m.r);
    }
    mirror_lower(H);
    H.diagonal().array() += 1e-9;
    if (!fit_slope) {
      H.block<2, 5>(2, 0).setZero();
      H.block<5, 2>(0, 2).setZero();
      H(2, 2) = H(3, 3) = 1.0;
      g.segment<2>(2).setZero();
    }
    Eigen::Matrix<double, 5, 1> step = H.ldlt().solve(-g);
    if (!step.allFinite()) break;
    Local next = m;
    for (int half = 0; half <= 12; ++half, step *= 0.5) {
      next = m;
      next.c += step.head<2>();
      next.s += step.segment<2>(2);
      next.r = std::clamp(m.r + step(4), min_r, max_r);
      if (!backtrack) break;
      const double next_cost = cylinder_cost(q, keep, next);
      if (next_cost <= current) {
        current = next_cost;
        break;
      }
      if (half == 12) return;
    }
    m = next;
    if (step.norm() < 1e-6) break;
  }
}

// The fit from `m`, and its RMS distance. Full Gauss-Newton steps, unless they end farther from
// the points than the start: the returns of a thin stem span a few centimetres across the line
// of sight, its centre's depth is barely determined, and full steps had run off to the radius
// bound with residuals of metres (a 0.10 m stem at 6.6 m lost); such a fit is done again from
// the start with steps that never raise the cost.
double solve(std::span<const Eigen::Vector3d> q, const std::vector<char>& keep, Local& m,
             bool fit_slope, double min_r, double max_r) {
  const Local start = m;
  cylinder_gauss_newton(q, keep, m, fit_slope, min_r, max_r, false);
  double cost = cylinder_cost(q, keep, m);
  if (!(cost <= cylinder_cost(q, keep, start))) {
    m = start;
    cylinder_gauss_newton(q, keep, m, fit_slope, min_r, max_r, true);
    cost = cylinder_cost(q, keep, m);
  }
  const double n = double(std::count(keep.begin(), keep.end(), char(1)));
  return n > 0 ? std::sqrt(cost / n) : 0.0;
}

// Per-bin circle fits (config.start_bin_m of local height, at least min_points each): the
// median centre and radius replace the start when at least three bins fit.
void robust_start(std::span<const Eigen::Vector3d> q, const CylinderFitConfig& config, Local& m) {
  if (!(config.start_bin_m > 0)) return;
  double lo = 1e30, hi = -1e30;
  for (const auto& p : q) {
    lo = std::min(lo, p.z());
    hi = std::max(hi, p.z());
  }
  const int bins = int((hi - lo) / config.start_bin_m) + 1;
  if (bins < 3) return;
  std::vector<std::vector<Eigen::Vector2d>> by_bin(static_cast<std::size_t>(bins));
  for (const auto& p : q)
    by_bin[std::size_t(std::min(bins - 1, int((p.z() - lo) / config.start_bin_m)))].push_back(
        p.head<2>());
  std::vector<double> cx, cy, r;
  for (const auto& pts : by_bin) {
    if (pts.size() < config.min_points) continue;
    const Circle c = fit_circle(pts, config.min_radius_m, config.max_radius_m, 20);
    if (!c.ok) continue;
    cx.push_back(c.center.x());
    cy.push_back(c.center.y());
    r.push_back(c.radius_m);
  }
  if (r.size() < 3) return;
  auto median = [](std::vector<double>& v) {
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
  };
  m = Local{{median(cx), median(cy)}, Eigen::Vector2d::Zero(), median(r)};
}

}  // namespace

Cylinder fit_cylinder(std::span<const Eigen::Vector3d> points, const Eigen::Vector3d& axis_point,
                      const Eigen::Vector3d& axis_direction, const CylinderFitConfig& config) {
  Cylinder cyl;
  if (points.size() < config.min_points) return cyl;
  Eigen::Vector3d origin = axis_point;
  Eigen::Vector3d dir = axis_direction.normalized();
  std::vector<Eigen::Vector3d> q(points.size());
  std::vector<char> keep(points.size(), 1);
  Local m;
  double rms = 0;
  for (int round = 0; round < 2; ++round) {
    const Eigen::Matrix3d R =
        Eigen::Quaterniond::FromTwoVectors(dir, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    for (std::size_t i = 0; i < points.size(); ++i) q[i] = R * (points[i] - origin);
    // Start: the bounded circle fit of the points projected along the axis, or, when the points
    // span several height bins, the median centre and radius of per-bin fits (a branch whorl
    // pulls one bin, not the median).
    std::vector<Eigen::Vector2d> xy;
    for (std::size_t i = 0; i < q.size(); ++i)
      if (keep[i]) xy.push_back(q[i].head<2>());
    const Circle c0 = fit_circle(xy, config.min_radius_m, config.max_radius_m, 20);
    if (!c0.ok) return cyl;
    m = Local{c0.center, Eigen::Vector2d::Zero(), c0.radius_m};
    if (round == 0) robust_start(q, config, m);
    for (int trim = 0; trim <= config.trim_rounds; ++trim) {
      rms = solve(q, keep, m, config.fit_direction, config.min_radius_m, config.max_radius_m);
      if (trim == config.trim_rounds) break;
      // With the binned start, the trim scale from the median absolute residual too: branch
      // points inflate an RMS.
      std::vector<double> res;
      for (std::size_t i = 0; i < q.size(); ++i)
        if (keep[i]) res.push_back(std::abs((q[i].head<2>() - m.c - m.s * q[i].z()).norm() - m.r));
      std::nth_element(res.begin(), res.begin() + res.size() / 2, res.end());
      const double scale =
          config.start_bin_m > 0 ? std::min(rms, 1.4826 * res[res.size() / 2]) : rms;
      const double thr = std::max(config.min_trim_m, config.trim_sigmas * scale);
      std::size_t kept = 0;
      bool changed = false;
      for (std::size_t i = 0; i < q.size(); ++i) {
        const bool k = std::abs((q[i].head<2>() - m.c - m.s * q[i].z()).norm() - m.r) <= thr;
        changed |= (k != bool(keep[i]));
        keep[i] = k;
        kept += k;
      }
      if (kept < config.min_points) return cyl;
      if (!changed) break;
    }
    // Back to the cloud's frame; a second round re-levels the local frame on the new axis.
    const Eigen::Matrix3d Rt = R.transpose();
    origin = origin + Rt * Eigen::Vector3d(m.c.x(), m.c.y(), 0.0);
    dir = (Rt * Eigen::Vector3d(m.s.x(), m.s.y(), 1.0)).normalized();
    if (!config.fit_direction) break;
  }
  if (dir.z() < 0) dir = -dir;
  cyl.point = origin;
  cyl.direction = dir;
  cyl.radius_m = m.r;
  cyl.residual_m = rms;
  cyl.inliers.clear();
  for (std::size_t i = 0; i < keep.size(); ++i)
    if (keep[i]) cyl.inliers.push_back(i);
  cyl.ok = origin.allFinite() && dir.allFinite() && std::isfinite(m.r);
  return cyl;
}

}  // namespace fieldlidar::forest
