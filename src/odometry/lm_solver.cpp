// seed 002, step d: Levenberg-Marquardt over edge-to-line and point-to-plane distances, 6 DoF,
// Cauchy weights, with the degenerate directions of the normal matrix held at the prior.

#include "fieldlidar/odometry/lm_solver.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

#include "skew.hpp"

namespace fieldlidar::odometry {

namespace {

using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;

using detail::skew;

struct System {
  Mat6 H = Mat6::Zero();
  Vec6 g = Vec6::Zero();
  double cost = 0;
  std::size_t count = 0;
};

/// Normal equations at pose T. Residual of an edge: the 3-vector from the line to the point
/// (perpendicular part); of a plane: the signed distance. Jacobians for T <- exp(xi) * T with xi =
/// (rotation, translation): d(Tp)/dxi = [-[Tp]x, I].
System build(std::span<const Correspondence> matches, const Pose& T, double scale) {
  System s;
  const double c2 = scale * scale;
  const Eigen::Matrix3d R = T.linear();
  const Eigen::Vector3d t = T.translation();
  for (const auto& m : matches) {
    const Eigen::Vector3d q = R * m.point_lidar + t;
    const Eigen::Vector3d d = q - m.map_point;
    ++s.count;
    if (m.is_edge) {
      // Perpendicular part of d; J = P [-[q]x, I] = [-(P [q]x), P] with P = I - u u^T.
      const Eigen::Vector3d r = d - m.direction * m.direction.dot(d);
      const double e2 = r.squaredNorm();
      s.cost += c2 * std::log1p(e2 / c2);
      const double w = 1.0 / (1.0 + e2 / c2);
      const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() - m.direction * m.direction.transpose();
      Eigen::Matrix<double, 6, 3> Jt;  // J^T
      Jt.topRows<3>() = (P * skew(q)).transpose() * -1.0;
      Jt.bottomRows<3>() = P;  // symmetric
      s.H.noalias() += Jt.lazyProduct(w * Jt.transpose());
      s.g.noalias() += Jt * (w * r);
    } else {
      const double r = m.direction.dot(d);
      s.cost += c2 * std::log1p(r * r / c2);
      const double w = 1.0 / (1.0 + r * r / c2);
      Vec6 Jt;  // J^T = [q x n; n]
      Jt.head<3>() = q.cross(m.direction);
      Jt.tail<3>() = m.direction;
      s.H.noalias() += (w * Jt) * Jt.transpose();
      s.g.noalias() += (w * r) * Jt;
    }
  }
  return s;
}

struct Degeneracy {
  Eigen::Vector2d ratio = Eigen::Vector2d::Ones();  ///< (translation, rotation)
  Mat6 keep = Mat6::Identity();  ///< projects an update off the degenerate directions
};

/// The information on one block (rows/columns at `a`) with the other (at `b`) marginalised out:
/// H_aa - H_ab H_bb^-1 H_ba.
Eigen::Matrix3d marginal(const Mat6& H, int a, int b) {
  const Eigen::Matrix3d Hbb = H.block<3, 3>(b, b);
  const Eigen::Matrix3d Hab = H.block<3, 3>(a, b);
  const double eps = 1e-12 * std::max(1.0, Hbb.trace());
  const Eigen::Matrix3d inv = (Hbb + eps * Eigen::Matrix3d::Identity()).inverse();
  return H.block<3, 3>(a, a) - Hab * inv * Hab.transpose();
}

Degeneracy degeneracy(const Mat6& H, double min_ratio) {
  Degeneracy d;
  for (int block = 0; block < 2; ++block) {  // 0: translation (rows 3-5), 1: rotation (rows 0-2)
    const int a = block == 0 ? 3 : 0, b = 3 - a;
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
    eig.computeDirect(marginal(H, a, b));
    const Eigen::Vector3d l = eig.eigenvalues().cwiseMax(0.0);
    d.ratio(block) = l(2) > 0 ? l(0) / l(2) : 0.0;
    for (int i = 0; i < 3; ++i)
      if (l(2) <= 0 || l(i) < min_ratio * l(2)) {
        const Eigen::Vector3d v = eig.eigenvectors().col(i);
        d.keep.block<3, 3>(a, a) -= v * v.transpose();
      }
  }
  return d;
}

}  // namespace

Pose se3_exp(const Vec6& xi) {
  Pose T = Pose::Identity();
  const Eigen::Vector3d w = xi.head<3>();
  const double a = w.norm();
  if (a > 1e-12) T.linear() = Eigen::AngleAxisd(a, w / a).toRotationMatrix();
  T.translation() = xi.tail<3>();
  return T;
}

LmResult solve_lm(std::span<const Correspondence> matches, const Pose& T_world_lidar,
                  const LmConfig& config) {
  LmResult out;
  out.T_world_lidar = T_world_lidar;
  if (matches.size() < 6) return out;
  double lambda = config.initial_lambda;
  System sys = build(matches, out.T_world_lidar, config.robust_scale_m);
  Eigen::SelfAdjointEigenSolver<Mat6> eig(sys.H / double(sys.count));
  out.eigenvalues = eig.eigenvalues();
  const Degeneracy dg = degeneracy(sys.H, config.degenerate_ratio);
  out.information_ratio = dg.ratio;
  out.degenerate = dg.ratio.minCoeff() < config.degenerate_ratio;
  if (config.solver == LmSolver::kCeres) return refine_with_ceres(matches, config, out);
  const Mat6& keep = dg.keep;
  for (int it = 0; it < config.max_iterations; ++it) {
    Mat6 A = sys.H;
    A.diagonal() += lambda * sys.H.diagonal();
    Vec6 dx = -A.ldlt().solve(sys.g);
    if (out.degenerate && config.hold_degenerate) dx = keep * dx;
    const Pose T_new = se3_exp(dx) * out.T_world_lidar;
    const System trial = build(matches, T_new, config.robust_scale_m);
    ++out.iterations;
    if (trial.cost <= sys.cost) {
      out.T_world_lidar = T_new;
      sys = trial;
      lambda = std::max(lambda * 0.3, 1e-9);
      if (dx.norm() < config.min_step) {
        out.converged = true;
        break;
      }
    } else {
      lambda *= 10;
      if (lambda > 1e4) break;
    }
  }
  out.rms_residual_m = std::sqrt(sys.cost / double(sys.count));
  return out;
}

}  // namespace fieldlidar::odometry
