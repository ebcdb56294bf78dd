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
  double total = 0;
  int degenerate = 0;
  for (const auto& r : res) total += r.timings.total_ms, degenerate += r.degenerate;
  std::printf("  mean %.2f ms per frame, %d degenerate frames\n", total / res.size(), degenerate);
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
