// Ground segmentation on simulated scenes, where the truth is exact.

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

// Measured F1: lawn VLP-16 0.983, OS1-64 0.989; terrain VLP-16 0.980, HDL-32E 0.989; forest
// VLP-16 0.981, OS1-64 0.991. The VLP-16 terrain frame meets the 0.98 by a few points
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

}  // namespace
}  // namespace fieldlidar::segmentation
