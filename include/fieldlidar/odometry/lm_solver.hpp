#pragma once
/// \file seed 002, step d: the 6-DoF transform that minimises edge-to-line and point-to-plane
/// distances, by a compact Levenberg-Marquardt with robust weights.

#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "fieldlidar/core/pose.hpp"

namespace fieldlidar::odometry {

/// A point of the sweep (lidar frame) matched to a line or a plane of the map (world frame).
struct Correspondence {
  Eigen::Vector3d point_lidar;
  Eigen::Vector3d map_point;  ///< a point of the line or plane
  Eigen::Vector3d direction;  ///< unit line direction, or unit plane normal
  bool is_edge = false;
};

/// Who minimises the problem: the compact Eigen LM of lm_solver.cpp, or Ceres' LM on the same
/// residuals, kernel, increment and stopping rule (only when built with Ceres: ceres_available()).
enum class LmSolver { kEigenLm, kCeres };

struct LmConfig {
  LmSolver solver = LmSolver::kEigenLm;
  int max_iterations = 4;        ///< LM steps per set of correspondences
  double initial_lambda = 1e-4;  ///< damping relative to the normal matrix' diagonal
  double robust_scale_m = 0.1;   ///< Cauchy (edge, plane) kernel width
  double min_step = 1e-6;        ///< stop when the update (m, rad) is smaller
  /// Degeneracy (Zhang et al. 2016, "On degeneracy of optimization-based state estimation
  /// problems"), made unit-free: the information on the translation with the rotation
  /// marginalised out (Schur complement of the normal matrix), and on the rotation with the
  /// translation marginalised out; a block whose smallest / largest eigenvalue is below this has a
  /// direction the matches barely constrain. A simulated featureless corridor (VLP-16, 3 cm
  /// range noise) gives about 0.002 along it, not 0 (0.008-0.009 when planes were fitted to 5
  /// points): noisy plane normals tilt at random and lend the direction some information.
  /// Greenhouse aisles: median 0.08.
  double degenerate_ratio = 0.01;
  /// Keep the prior along degenerate directions (LOAM's solution remapping). Off: on the
  /// simulated greenhouse (600 frames, VLP-16) holding them raised the drift from 0.20 % to
  /// 0.47 % (the turn at the aisle end is flagged, and the IMU/wheel prior is worse there).
  bool hold_degenerate = false;
};

struct LmResult {
  Pose T_world_lidar = Pose::Identity();
  int iterations = 0;
  bool converged = false;
  double rms_residual_m = 0.0;
  Eigen::Matrix<double, 6, 1> eigenvalues = Eigen::Matrix<double, 6, 1>::Zero();  ///< ascending,
                                                                                  ///< / count
  /// Smallest / largest eigenvalue of the marginal information on (translation, rotation).
  Eigen::Vector2d information_ratio = Eigen::Vector2d::Ones();
  bool degenerate = false;  ///< information_ratio below LmConfig::degenerate_ratio
};

/// Refines `T_world_lidar` from the correspondences (left perturbation, rotation then
/// translation); the correspondences are fixed during the call.
LmResult solve_lm(std::span<const Correspondence> matches, const Pose& T_world_lidar,
                  const LmConfig& config);

/// The steps of solve_lm after its degeneracy analysis, taken by Ceres (ceres_solver.cpp): `out`
/// holds the start pose and the diagnostics; pose, iterations, convergence and RMS are filled in.
/// Raises Error when fieldlidar was built without Ceres.
LmResult refine_with_ceres(std::span<const Correspondence> matches, const LmConfig& config,
                           LmResult out);
bool ceres_available();
/// "eigen_lm" / "ceres" <-> LmSolver; parse_lm_solver raises Error naming the value.
LmSolver parse_lm_solver(const std::string& name);
const char* lm_solver_name(LmSolver solver);

/// SE(3) exponential of (rotation vector, translation) as used by the solver's update.
Pose se3_exp(const Eigen::Matrix<double, 6, 1>& xi);

}  // namespace fieldlidar::odometry
