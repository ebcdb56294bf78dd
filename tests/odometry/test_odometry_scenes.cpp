// The forest and terrain drives (VLP-16, IMU and wheels): a short stretch of each as a regression
// bound; the full runs are reported from `fieldlidar simulate` + `fieldlidar odometry`.

#include <cstdio>

#include <gtest/gtest.h>

#include "odometry_eval.hpp"

namespace fieldlidar::odometry::test {
namespace {

TrajectoryErrors run_scene(sim::SceneKind kind, int frames, const char* name) {
  const auto s = simulate_sequence(kind, 0, frames);
  OdometryConfig cfg;
  apply_env(cfg);  // tuning knobs, none set in a test run
  const auto e = trajectory_errors(run(s, cfg, true), relative_to_first(s.truth), 2.0);
  std::printf("%s: path %.2f m, drift %.3f %% (2 m), RPE %.2f cm / %.3f deg, ATE %.3f m\n", name,
              e.path_m, e.drift_pct, 100 * e.rpe_t_m, e.rpe_r_deg, e.ate_m);
  return e;
}

TEST(OdometryScenes, TerrainVlp16) {
  // Measured: RPE 1.80 cm / 0.055 deg, ATE 0.030 m (2.09 cm / 0.072 deg, 0.039 m while coarse
  // re-alignments that gained almost nothing were kept). Fits over 5 map points: 1.16 cm /
  // 0.030 m, over 8: 1.45 cm / 0.026 m. Of the 1.80 cm, frames 1 and 2 (6.1 and 3.5 cm, a
  // one-sweep map) make about 0.9: 10 points reach farther in the sparse first map and smooth
  // over the rocks (LocalMapConfig::neighbours).
  const auto e = run_scene(sim::SceneKind::kTerrain, 60, "terrain VLP-16, 60 frames");
  EXPECT_LT(e.rpe_t_m, 0.022);
  EXPECT_LT(e.rpe_r_deg, 0.08);
  EXPECT_LT(e.ate_m, 0.06);
}

TEST(OdometryScenes, ForestVlp16) {
  // Measured: RPE 1.13 cm / 0.042 deg, ATE 0.011 m (1.02 cm / 0.032 deg while coarse
  // re-alignments gaining under 0.02 of the features were kept; 5-point fits: 1.57 cm / 0.304
  // deg, 0.035 m): the per-frame rotation is still several times the greenhouse's (few planes
  // among the trunks for 16 beams).
  const auto e = run_scene(sim::SceneKind::kForest, 60, "forest VLP-16, 60 frames");
  EXPECT_LT(e.rpe_t_m, 0.025);
  EXPECT_LT(e.rpe_r_deg, 0.5);
  EXPECT_LT(e.ate_m, 0.06);
}

}  // namespace
}  // namespace fieldlidar::odometry::test
