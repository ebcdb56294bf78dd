// The standing-start scenario over the whole lap: after waiting 5 s for the operator, the mower
// still records the lawn's boundary as in the default scenario (seed 000 targets).

#include <gtest/gtest.h>

#include "seed_targets.hpp"
#include "standing_start.hpp"

namespace fieldlidar::loops {
namespace {

using standing_start::expect_standing_start;
using standing_start::print;
using standing_start::read_standing_start;

// Measured (Release, VLP-16, odometry poses, scene seed 0): 767 frames, following in 764, stopped
// by command; boundary mean 0.032 m, Hausdorff 0.233 m; no frame moving below L_s, no target
// switch; the standing phase as in test_standing_start.cpp.
TEST(StandingStart, WholeLapMeetsTheSeedTargets) {
  const auto scene = sim::make_lawn_scene(lawn_config(Scenario::kStandingStart), 0);
  ClosedLoopConfig cfg;
  cfg.max_time_s = 120.0;  // a 69 m lap at 1 m/s after 5 s standing
  const auto r = run_closed_loop(scene, SensorModel::vlp16(), cfg);
  const auto s = read_standing_start(r);
  print("standing-start, whole lap", r, s);
  expect_standing_start(s);
  test::expect_seed_000_lap_targets(r);
}

}  // namespace
}  // namespace fieldlidar::loops
