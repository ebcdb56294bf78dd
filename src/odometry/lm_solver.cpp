// seed 002, step d: Levenberg-Marquardt over edge-to-line and point-to-plane distances, 6 DoF,
// Cauchy weights, with the degenerate directions of the normal matrix held at the prior.

#include "fieldlidar/odometry/lm_solver.hpp"

#include <cmath>

#include <Eigen/Eigenvalues>

namespace fieldlidar::odometry {

namespace {

using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;

Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

struct System {
  Mat6 H = Mat6::Zero();
  Vec6 g = Vec6::Zero();
  double cost = 0;
  std::size_t count = 0;
};

/// Normal equations at pose T. Residual of an edge: the 3-vector from the line to the point
/// (perpendicular part); of a plane: the signed distance. Jacobians for T <- exp(xi) * T with
/// xi = (rotation, translation): d(Tp)/dxi = [-[Tp]x, I].
System build(std::span<const Correspondence> matches, const Pose& T, double scale) {
  System s;
  const double c2 = scale * scale;
  for (const auto& m : matches) {
    const Eigen::Vector3d q = T * m.point_lidar;
    Eigen::Matrix<double, 3, 6> Jp;
    Jp.leftCols<3>() = -skew(q);
    Jp.rightCols<3>().setIdentity();
    if (m.is_edge) {
      const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() - m.direction * m.direction.transpose();
      const Eigen::Vector3d r = P * (q - m.map_point);
      const double e2 = r.squaredNorm();
      const double w = 1.0 / (1.0 + e2 / c2);
      const Eigen::Matrix<double, 3, 6> J = P * Jp;
      s.H.noalias() += w * J.transpose() * J;
      s.g.noalias() += w * J.transpose() * r;
      s.cost += c2 * std::log1p(e2 / c2);
    } else {
      const double r = m.direction.dot(q - m.map_point);
      const double w = 1.0 / (1.0 + r * r / c2);
      const Eigen::Matrix<double, 1, 6> J = m.direction.transpose() * Jp;
      s.H.noalias() += w * J.transpose() * J;
      s.g.noalias() += w * J.transpose() * r;
      s.cost += c2 * std::log1p(r * r / c2);
    }
    ++s.count;
  }
  return s;
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
  // Degenerate directions from the eigen decomposition of the first normal matrix (Zhang et al.,
  // "On degeneracy of optimization-based state estimation problems").
  Eigen::SelfAdjointEigenSolver<Mat6> eig(sys.H / double(sys.count));
  out.eigenvalues = eig.eigenvalues();
  Mat6 keep = Mat6::Identity();
  {
    Mat6 V = eig.eigenvectors().transpose();  // rows = eigenvectors
    Mat6 V2 = V;
    for (int i = 0; i < 6; ++i)
      if (eig.eigenvalues()(i) < config.degenerate_eigenvalue) {
        V2.row(i).setZero();
        out.degenerate = true;
      }
    if (out.degenerate) keep = V.inverse() * V2;
  }
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
