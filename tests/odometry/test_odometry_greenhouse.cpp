// Accuracy on the simulated greenhouse (VLP-16 with IMU and wheels).

#include <cstdio>
#include <cstdlib>

#include <gtest/gtest.h>

#include "odometry_eval.hpp"

namespace fieldlidar::odometry::test {
namespace {

int env_int(const char* name, int fallback) {
  const char* v = std::getenv(name);
  return v ? std::atoi(v) : fallback;
}

void report(const char* what, const TrajectoryErrors& e) {
  std::printf("%-34s path %.2f m  drift %.3f %%  RPE %.2f cm / %.3f deg  ATE %.3f m\n", what,
              e.path_m, e.drift_pct, 100 * e.rpe_t_m, e.rpe_r_deg, e.ate_m);
}

// Tuning / report run over many frames: FIELDLIDAR_ODOM_FIRST, FIELDLIDAR_ODOM_FRAMES.
TEST(OdometryGreenhouse, DISABLED_Report) {
  const auto s = simulate_sequence(sim::SceneKind::kGreenhouse, env_int("FIELDLIDAR_ODOM_FIRST", 0),
                                   env_int("FIELDLIDAR_ODOM_FRAMES", 300),
                                   std::uint64_t(env_int("FIELDLIDAR_ODOM_SEED", 0)));
  const auto truth = relative_to_first(s.truth);
  const double seg = 10.0;
  OdometryConfig def;
  std::vector<OdometryResult> res;
  report("default (map, IMU+wheels)", trajectory_errors(run(s, def, true, &res), truth, seg));
  StepTimings t;
  int degenerate = 0;
  double it = 0, inl = 0;
  for (const auto& r : res) {
    t.total_ms += r.timings.total_ms, t.deskew_ms += r.timings.deskew_ms;
    t.preprocess_ms += r.timings.preprocess_ms, t.features_ms += r.timings.features_ms;
    t.match_ms += r.timings.match_ms, t.map_ms += r.timings.map_ms;
    degenerate += r.degenerate, it += r.iterations, inl += r.inliers;
  }
  const double n = double(res.size());
  std::printf("  ms/frame total %.2f (deskew %.2f pre %.2f feat %.2f match %.2f map %.2f), "
              "%.1f LM steps, %.0f matches, %d degenerate frames\n",
              t.total_ms / n, t.deskew_ms / n, t.preprocess_ms / n, t.features_ms / n,
              t.match_ms / n, t.map_ms / n, it / n, inl / n, degenerate);
  report("default without IMU/wheels", trajectory_errors(run(s, def, false), truth, seg));
  OdometryConfig f2f;
  f2f.target = MatchTarget::kPreviousFrame;
  f2f.preprocess.split_ground = true;
  f2f.preprocess.drop_small_clusters = true;
  report("seed (frame to frame, ground+clusters)", trajectory_errors(run(s, f2f, true), truth, seg));
  OdometryConfig gc = def;
  gc.preprocess.split_ground = true;
  gc.preprocess.drop_small_clusters = true;
  report("map + seed ground/clusters", trajectory_errors(run(s, gc, true), truth, seg));
}

}  // namespace
}  // namespace fieldlidar::odometry::test
namespace fieldlidar::odometry::test {
TEST(OdometryGreenhouse, DISABLED_Debug) {
  const auto s = simulate_sequence(sim::SceneKind::kGreenhouse, 0, 30, 0);
  const auto truth = relative_to_first(s.truth);
  std::vector<OdometryResult> res;
  const auto est = run(s, OdometryConfig{}, std::getenv("IMU") != nullptr, &res);
  for (std::size_t i = 0; i < est.size(); ++i) {
    const Pose e = truth[i].inverse() * est[i];
    std::printf("%zu t %.3f %.3f %.3f err %.3f rot %.3f inl %zu it %d reg %d\n", i,
                truth[i].translation().x(), truth[i].translation().y(), yaw_of(truth[i]),
                e.translation().norm(), angle_deg(e.linear()), res[i].inliers, res[i].iterations,
                int(res[i].registered));
  }
}
}  // namespace fieldlidar::odometry::test
namespace fieldlidar::odometry::test {
TEST(OdometryGreenhouse, DISABLED_Same) {
  auto s = simulate_sequence(sim::SceneKind::kGreenhouse, 0, 1, 0);
  OdometryConfig cfg;
  cfg.deskew.enabled = false;
  if (std::getenv("NOEDGE")) cfg.features.edges_per_sector = 0, cfg.features.curvature_threshold = 10;
  if (std::getenv("NOPLANE")) cfg.features.planes_per_sector = 0;
  LidarOdometry odo(s.sensor, cfg);
  auto f = s.frames[0];
  odo.register_frame(f);
  for (int k = 0; k < 3; ++k) {
    f.stamp_s += 0.1;
    const auto r = odo.register_frame(f);
    std::printf("t %.4f %.4f %.4f rot %.3f inl %zu it %d eig %.3g %.3g %.3g %.3g %.3g %.3g\n",
                r.T_world_lidar.translation().x(), r.T_world_lidar.translation().y(),
                r.T_world_lidar.translation().z(), angle_deg(r.T_world_lidar.linear()), r.inliers,
                r.iterations, r.eigenvalues(0), r.eigenvalues(1), r.eigenvalues(2),
                r.eigenvalues(3), r.eigenvalues(4), r.eigenvalues(5));
  }
}
}  // namespace fieldlidar::odometry::test
