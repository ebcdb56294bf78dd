// Ground segmentation on simulated scenes, where the truth is exact.

#include <algorithm>
#include <cstdio>

#include <gtest/gtest.h>

#include "fieldlidar/segmentation/segment.hpp"
#include "fieldlidar/sim/lidar_simulator.hpp"
#include "fieldlidar/sim/motion.hpp"
#include "fieldlidar/sim/scenes.hpp"

namespace fieldlidar::segmentation {
namespace {

GroundScore sim_score(sim::SceneKind kind, const SensorModel& sensor, double t0_s,
                      std::uint64_t seed, GroundMethod method = GroundMethod::kRobust) {
  const sim::Scene scene = sim::make_scene(kind, seed);
  const auto motion = sim::drive_scene_route(scene, t0_s + 1.0);
  const sim::LidarSimulator lidar(scene, sensor);
  const sim::SimFrame frame = lidar.scan(t0_s, motion.lidar_pose_fn());
  GroundConfig cfg;
  cfg.method = method;
  const GroundResult r = segment_ground(frame.cloud, sensor, cfg);
  const std::vector<std::uint16_t> ground{std::uint16_t(LabelClass::kGround)};
  const std::vector<std::uint16_t> ignored{std::uint16_t(LabelClass::kUnlabelled)};
  return score_ground(frame.cloud, r.is_ground, frame.cloud.labels, ground, ignored);
}

struct Case {
  sim::SceneKind kind;
  const char* sensor;
  double t0_s;
  /// The 0.98, or a tighter regression bound just under the measured F1 where that is
  /// higher; the frames that miss 0.98 have a regression bound only.
  double min_f1;
  std::uint64_t seed = 7;  ///< scene seed
};

class SimGround : public ::testing::TestWithParam<Case> {};

TEST_P(SimGround, RobustF1) {
  const Case c = GetParam();
  const GroundScore s = sim_score(c.kind, *SensorModel::preset(c.sensor), c.t0_s, c.seed);
  std::printf("%s %s: P %.4f R %.4f F1 %.4f\n", sim::to_string(c.kind).c_str(), c.sensor,
              s.precision, s.recall, s.f1);
  EXPECT_GE(s.f1, c.min_f1) << sim::to_string(c.kind) << " " << c.sensor << " P " << s.precision
                            << " R " << s.recall;
}

// Measured F1: lawn VLP-16 0.983, OS1-64 0.991; terrain VLP-16 0.980, HDL-32E 0.989; forest
// VLP-16 0.981, OS1-64 0.992. The VLP-16 terrain frame meets the 0.98 by a few points
// (0.9801): 40 m out the top of a 30 deg hillside rises in steps of one scan line per cell, the
// skirts of rocks and bushes pass as ground, and the near rim of a pit is taken for a face. It
// owes 0.979 -> 0.980 to the ground running on to the foot of a bush
// (RobustGroundConfig::face_flat_gap_m), 0.970 -> 0.979 to the line continuation
// (RobustGroundConfig::max_line_slope_deg) and the pit walls (RobustGroundConfig::rim_above_m).
// In the forest frame of seed 11 at 9 s (VLP-16 0.982) the ground 5-15 m out lies about a metre
// above the robot's, behind a rise its cells see as single scan lines: without the line
// continuation F1 is 0.954.
INSTANTIATE_TEST_SUITE_P(Scenes, SimGround,
                         ::testing::Values(Case{sim::SceneKind::kLawn, "vlp16", 1.0, 0.98},
                                           Case{sim::SceneKind::kLawn, "os1-64", 4.0, 0.986},
                                           Case{sim::SceneKind::kTerrain, "vlp16", 1.0, 0.98},
                                           Case{sim::SceneKind::kTerrain, "hdl32e", 6.0, 0.987},
                                           Case{sim::SceneKind::kForest, "vlp16", 1.0, 0.98},
                                           Case{sim::SceneKind::kForest, "os1-64", 5.0, 0.989},
                                           Case{sim::SceneKind::kForest, "vlp16", 9.0, 0.98, 11}),
                         [](const auto& info) {
                           std::string s = sim::to_string(info.param.kind) + "_" +
                                           info.param.sensor + "_" +
                                           std::to_string(int(info.param.t0_s)) + "_seed" +
                                           std::to_string(info.param.seed);
                           for (auto& ch : s)
                             if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
                           return s;
                         });

// The frames above are single frames. Over eight more VLP-16 frames per scene (seeds 21-24 at
// 2 s and 7 s) the typical F1 is lower on the terrain and forest scenes than on the asserted
// frames. Measured: lawn mean 0.9856 (0.9805-0.9909), terrain mean 0.9733 (0.9670-0.9804),
// forest mean 0.9737 (0.9476-0.9844). In the worst forest frame (seed 24, 7 s) the ground falls
// away at 10 deg ahead of the robot: 10-15 m out a scan line lies 1.1 m below the one 6 m
// nearer, one line per cell, beyond the bend tolerance and short of the descent gap.
struct Spread {
  sim::SceneKind kind;
  double min_mean_f1, min_f1;
};

class SimGroundSpread : public ::testing::TestWithParam<Spread> {};

TEST_P(SimGroundSpread, RobustF1OverSeedsAndTimes) {
  const Spread c = GetParam();
  const SensorModel vlp = *SensorModel::preset("vlp16");
  double sum = 0, worst = 1;
  int n = 0;
  for (std::uint64_t seed : {21, 22, 23, 24})
    for (double t0 : {2.0, 7.0}) {
      const GroundScore s = sim_score(c.kind, vlp, t0, seed);
      std::printf("%s vlp16 seed %d t %.0f: P %.4f R %.4f F1 %.4f\n",
                  sim::to_string(c.kind).c_str(), int(seed), t0, s.precision, s.recall, s.f1);
      sum += s.f1;
      worst = std::min(worst, s.f1);
      ++n;
    }
  std::printf("%s vlp16: mean F1 %.4f, worst %.4f over %d frames\n", sim::to_string(c.kind).c_str(),
              sum / n, worst, n);
  EXPECT_GE(sum / n, c.min_mean_f1);
  EXPECT_GE(worst, c.min_f1);
}

INSTANTIATE_TEST_SUITE_P(Scenes, SimGroundSpread,
                         ::testing::Values(Spread{sim::SceneKind::kLawn, 0.984, 0.979},
                                           Spread{sim::SceneKind::kTerrain, 0.972, 0.965},
                                           Spread{sim::SceneKind::kForest, 0.972, 0.945}),
                         [](const auto& info) { return sim::to_string(info.param.kind); });

}  // namespace
}  // namespace fieldlidar::segmentation
