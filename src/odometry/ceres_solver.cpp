// seed 002, step d by Ceres: the problem of solve_lm (edge-to-line and point-to-plane residuals,
// Cauchy kernel, left-multiplied 6-DoF increment, the same iteration budget and step tolerance)
// handed to Ceres' Levenberg-Marquardt, to compare the two solvers at equal accuracy.

#include <cmath>
#include <string>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/odometry/lm_solver.hpp"
#include "skew.hpp"

#if FIELDLIDAR_HAVE_CERES
#include <ceres/ceres.h>

#include <Eigen/Geometry>
#endif

namespace fieldlidar::odometry {

LmSolver parse_lm_solver(const std::string& name) {
  if (name == "eigen_lm") return LmSolver::kEigenLm;
  if (name == "ceres") return LmSolver::kCeres;
  throw Error("solver: '" + name + "' is not one of eigen_lm, ceres");
}

const char* lm_solver_name(LmSolver solver) {
  return solver == LmSolver::kCeres ? "ceres" : "eigen_lm";
}

#if FIELDLIDAR_HAVE_CERES

namespace {

using Vec6 = Eigen::Matrix<double, 6, 1>;

using detail::skew;

/// The parameter block: a pose as (quaternion x y z w, translation), 7 numbers. Its tangent is
/// solve_lm's increment xi = (rotation vector, translation) with x <- se3_exp(xi) * x. The cost
/// functions give their Jacobian in that tangent directly (first six columns, the seventh zero),
/// so the lift from tangent to ambient is [I6; 0] (as in F-LOAM's SE(3) parametrisation).
class LeftSe3 final : public ceres::Manifold {
 public:
  int AmbientSize() const override { return 7; }
  int TangentSize() const override { return 6; }
  bool Plus(const double* x, const double* delta, double* x_plus) const override {
    const Pose D = se3_exp(Eigen::Map<const Vec6>(delta));
    const Eigen::Quaterniond dq(D.linear());
    Eigen::Map<Eigen::Quaterniond> q_plus(x_plus);
    Eigen::Map<Eigen::Vector3d> t_plus(x_plus + 4);
    q_plus = (dq * Eigen::Map<const Eigen::Quaterniond>(x)).normalized();
    t_plus = D.linear() * Eigen::Map<const Eigen::Vector3d>(x + 4) + D.translation();
    return true;
  }
  bool PlusJacobian(const double*, double* jacobian) const override {
    Eigen::Map<Eigen::Matrix<double, 7, 6, Eigen::RowMajor>> J(jacobian);
    J.setZero();
    J.topRows<6>().setIdentity();
    return true;
  }
  bool Minus(const double* y, const double* x, double* y_minus_x) const override {
    Eigen::Quaterniond dq = Eigen::Map<const Eigen::Quaterniond>(y) *
                            Eigen::Map<const Eigen::Quaterniond>(x).conjugate();
    if (dq.w() < 0) dq.coeffs() = -dq.coeffs();
    const Eigen::AngleAxisd aa(dq);
    Eigen::Map<Vec6> out(y_minus_x);
    out.head<3>() = aa.angle() * aa.axis();
    out.tail<3>() = Eigen::Map<const Eigen::Vector3d>(y + 4) -
                    dq.toRotationMatrix() * Eigen::Map<const Eigen::Vector3d>(x + 4);
    return true;
  }
  bool MinusJacobian(const double*, double* jacobian) const override {
    Eigen::Map<Eigen::Matrix<double, 6, 7, Eigen::RowMajor>> J(jacobian);
    J.setZero();
    J.leftCols<6>().setIdentity();
    return true;
  }
};

/// The point q = T(x) q0, with q0 the feature already moved by the start pose.
Eigen::Vector3d moved(const double* x, const Eigen::Vector3d& q0) {
  return Eigen::Map<const Eigen::Quaterniond>(x) * q0 + Eigen::Map<const Eigen::Vector3d>(x + 4);
}

/// Edge: the 3-vector from the line to the point, P (q - a) with P = I - u u^T;
/// d/dxi = [-P [q]x, P].
class EdgeCost final : public ceres::SizedCostFunction<3, 7> {
 public:
  EdgeCost(const Eigen::Vector3d& q0, const Correspondence& m)
      : q0_(q0),
        a_(m.map_point),
        P_(Eigen::Matrix3d::Identity() - m.direction * m.direction.transpose()) {}
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const Eigen::Vector3d q = moved(parameters[0], q0_);
    Eigen::Map<Eigen::Vector3d> r(residuals);
    r = P_ * (q - a_);
    if (jacobians && jacobians[0]) {
      Eigen::Map<Eigen::Matrix<double, 3, 7, Eigen::RowMajor>> J(jacobians[0]);
      J.leftCols<3>() = -P_ * skew(q);
      J.middleCols<3>(3) = P_;
      J.col(6).setZero();
    }
    return true;
  }

 private:
  Eigen::Vector3d q0_, a_;
  Eigen::Matrix3d P_;
};

/// Plane: the signed distance n . (q - a); d/dxi = [(q x n)^T, n^T].
class PlaneCost final : public ceres::SizedCostFunction<1, 7> {
 public:
  PlaneCost(const Eigen::Vector3d& q0, const Correspondence& m)
      : q0_(q0), a_(m.map_point), n_(m.direction) {}
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const Eigen::Vector3d q = moved(parameters[0], q0_);
    residuals[0] = n_.dot(q - a_);
    if (jacobians && jacobians[0]) {
      Eigen::Map<Eigen::Matrix<double, 1, 7, Eigen::RowMajor>> J(jacobians[0]);
      J.leftCols<3>() = q.cross(n_).transpose();
      J.middleCols<3>(3) = n_.transpose();
      J(6) = 0;
    }
    return true;
  }

 private:
  Eigen::Vector3d q0_, a_, n_;
};

}  // namespace

bool ceres_available() {
  return true;
}

LmResult refine_with_ceres(std::span<const Correspondence> matches, const LmConfig& config,
                           LmResult out) {
  if (config.hold_degenerate)
    throw Error("lm.hold_degenerate: not available with solver ceres (use eigen_lm)");
  // The pose is solved relative to the start: x starts at the identity, so Ceres' relative
  // parameter tolerance (|dx| <= tol (|x| + tol), |x| = 1 + |t|) is solve_lm's absolute min_step.
  const Pose T0 = out.T_world_lidar;
  double x[7] = {0, 0, 0, 1, 0, 0, 0};
  LeftSe3 manifold;
  ceres::CauchyLoss loss(config.robust_scale_m);  // rho(s) = c^2 log(1 + s / c^2), as solve_lm
  ceres::Problem::Options po;
  po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  po.disable_all_safety_checks = true;
  ceres::Problem problem(po);
  problem.AddParameterBlock(x, 7, &manifold);
  for (const auto& m : matches) {
    const Eigen::Vector3d q0 = T0 * m.point_lidar;
    ceres::CostFunction* cost =
        m.is_edge ? static_cast<ceres::CostFunction*>(new EdgeCost(q0, m)) : new PlaneCost(q0, m);
    problem.AddResidualBlock(cost, &loss, x);
  }
  ceres::Solver::Options so;
  so.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  so.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;  // solve_lm: LDLT of the normal matrix
  so.max_num_iterations = config.max_iterations;         // accepted and rejected steps
  so.initial_trust_region_radius = 1.0 / config.initial_lambda;  // damping = diag / radius
  so.min_trust_region_radius = 1e-4;                             // solve_lm gives up at 1e4
  so.parameter_tolerance = config.min_step;
  so.function_tolerance = 0.0;  // solve_lm stops on the step only
  so.gradient_tolerance = 0.0;
  so.num_threads = 1;
  so.logging_type = ceres::SILENT;
  so.minimizer_progress_to_stdout = false;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);

  Pose dT = Pose::Identity();
  dT.linear() = Eigen::Map<const Eigen::Quaterniond>(x).toRotationMatrix();
  dT.translation() = Eigen::Map<const Eigen::Vector3d>(x + 4);
  out.T_world_lidar = dT * T0;
  out.iterations = int(summary.iterations.size()) - 1;  // the first entry is the start
  out.converged = summary.termination_type == ceres::CONVERGENCE;
  // Ceres' cost is half the sum of rho; solve_lm's RMS is sqrt(sum rho / count).
  out.rms_residual_m = std::sqrt(2.0 * summary.final_cost / double(matches.size()));
  return out;
}

#else

bool ceres_available() {
  return false;
}

LmResult refine_with_ceres(std::span<const Correspondence>, const LmConfig&, LmResult) {
  throw Error("solver: 'ceres' needs fieldlidar built with Ceres (libceres-dev); use eigen_lm");
}

#endif

}  // namespace fieldlidar::odometry
