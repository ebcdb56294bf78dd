// Ceres' LM (LmSolver::kCeres) against the Eigen LM on the same matching problem: the same pose,
// one solve and a short greenhouse sequence. Without Ceres the tests say so and skip.

#include <gtest/gtest.h>

#include "fieldlidar/core/error.hpp"
#include "odometry_eval.hpp"

namespace fieldlidar::odometry::test {
namespace {

double rotation_deg(const Pose& a, const Pose& b) {
  return angle_deg((a.inverse() * b).linear());
}

TEST(OdometryCeres, WithoutCeresTheChoiceRaises) {
  if (ceres_available()) GTEST_SKIP() << "built with Ceres: nothing to refuse";
  LmConfig lm;
  lm.solver = LmSolver::kCeres;
  std::vector<Correspondence> m(6, Correspondence{{1, 0, 0}, {1, 0, 0}, {1, 0, 0}, false});
  EXPECT_THROW(solve_lm(m, Pose::Identity(), lm), Error);
}

TEST(OdometryCeres, SolverNames) {
  EXPECT_EQ(parse_lm_solver("eigen_lm"), LmSolver::kEigenLm);
  EXPECT_EQ(parse_lm_solver("ceres"), LmSolver::kCeres);
  EXPECT_STREQ(lm_solver_name(LmSolver::kCeres), "ceres");
  EXPECT_THROW(parse_lm_solver("gauss_newton"), Error);
}

// Four planes around the origin and two vertical edges, seen from a pose 0.2 m and 3 deg off,
// with a few gross outliers: both solvers recover it and reach the same minimum.
TEST(OdometryCeres, OneSolveSamePose) {
  if (!ceres_available()) GTEST_SKIP() << "built without Ceres (libceres-dev): not compared";
  const Pose truth = make_pose(0.15, -0.1, 0.05, 0.02, -0.01, 0.05);
  std::vector<Correspondence> matches;
  const Eigen::Vector3d normals[] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.6, 0.8, 0}};
  for (int k = 0; k < 4; ++k)
    for (int i = 0; i < 40; ++i) {
      const Eigen::Vector3d& n = normals[k];
      const Eigen::Vector3d u = n.unitOrthogonal(), v = n.cross(u);
      const Eigen::Vector3d w = 5.0 * n + (i % 8 - 3.5) * u + (i / 8 - 2.0) * v;
      // A few gross outliers for the kernel.
      const Eigen::Vector3d wrong = (i % 13 == 0 ? 0.5 : 0.0) * n;
      matches.push_back({truth.inverse() * (w + wrong), 5.0 * n, n, false});
    }
  for (int e = 0; e < 2; ++e)
    for (int i = 0; i < 10; ++i) {
      const Eigen::Vector3d a(e ? -4.0 : 4.0, 3.0, 0.0), z(0, 0, 1);
      matches.push_back({truth.inverse() * (a + (i - 5) * 0.3 * z), a, z, true});
    }
  LmConfig lm;
  lm.max_iterations = 20;
  const auto eig = solve_lm(matches, Pose::Identity(), lm);
  lm.solver = LmSolver::kCeres;
  const auto cer = solve_lm(matches, Pose::Identity(), lm);
  // The outliers keep a little weight under the Cauchy kernel: 3 mm, 0.005 deg off the truth.
  EXPECT_LT((cer.T_world_lidar.translation() - truth.translation()).norm(), 0.01);
  EXPECT_LT(rotation_deg(cer.T_world_lidar, truth), 0.02);
  EXPECT_LT((cer.T_world_lidar.translation() - eig.T_world_lidar.translation()).norm(), 1e-5);
  EXPECT_LT(rotation_deg(cer.T_world_lidar, eig.T_world_lidar), 1e-4);
  EXPECT_EQ(cer.degenerate, eig.degenerate);
  EXPECT_NEAR(cer.rms_residual_m, eig.rms_residual_m, 1e-6);
}

// 12 greenhouse sweeps (VLP-16, IMU + wheels): every pose of the Ceres run within 0.1 mm and
// 0.002 deg of the Eigen run's.
TEST(OdometryCeres, SamePosesOnAGreenhouseSequence) {
  if (!ceres_available()) GTEST_SKIP() << "built without Ceres (libceres-dev): not compared";
  const auto s = simulate_sequence(sim::SceneKind::kGreenhouse, 20, 12);
  OdometryConfig cfg;
  const auto eig = run(s, cfg, true);
  cfg.lm.solver = LmSolver::kCeres;
  const auto cer = run(s, cfg, true);
  double worst_m = 0, worst_deg = 0;
  for (std::size_t i = 0; i < eig.size(); ++i) {
    worst_m = std::max(worst_m, (cer[i].translation() - eig[i].translation()).norm());
    worst_deg = std::max(worst_deg, rotation_deg(cer[i], eig[i]));
  }
  std::printf("ceres - eigen_lm over %zu sweeps: up to %.2e m, %.2e deg\n", eig.size(), worst_m,
              worst_deg);
  EXPECT_LT(worst_m, 1e-4);    // measured 8.1e-7 m
  EXPECT_LT(worst_deg, 2e-3);  // measured 1.5e-5 deg
}

}  // namespace
}  // namespace fieldlidar::odometry::test
