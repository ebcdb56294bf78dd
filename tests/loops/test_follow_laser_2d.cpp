// The seed 000 follow loop with a planar 2D laser at the mower's 0.45 m mount instead of a
// multi-beam LiDAR (SensorModel::laser_2d: 270 deg at the legs_2d bags' 0.35 deg steps): persons
// from people::LegPipeline2D with the shipped classifier (learned from the real legs_2d bags),
// the mower's pose from its wheels and IMU (DeadReckoningPoseSource). The operator walks the
// lawn's outline 3 m ahead at 1 m/s, beyond the classifier's 5.1 m reach whenever the mower lags.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "../people/shipped_legs_2d.hpp"
#include "fieldlidar/loops/closed_loop.hpp"
#include "fieldlidar/sim/lidar_simulator.hpp"
#include "seed_targets.hpp"

namespace fieldlidar::loops {
namespace {

ClosedLoopResult run_2d(Scenario s, std::uint64_t scene_seed = 0,
                        PoseSource poses = PoseSource::kOdometry) {
  const auto scene = sim::make_lawn_scene(lawn_config(s), scene_seed);
  ClosedLoopConfig cfg;
  cfg.legs_2d = fieldlidar::test::shipped_legs_2d();
  cfg.pose_source = poses;
  auto r = run_closed_loop(scene, SensorModel::laser_2d(), cfg);
  std::printf(
      "%s, 2D laser: frames %zu target chosen %zu held %zu following %zu stopped_by_command %d "
      "boundary mean %.3f m hausdorff %.3f m switches %zu off %zu occlusions %zu stop_delay %d "
      "resume_delay %d ATE %.3f m perception %.3f ms\n",
      to_string(s).c_str(), r.rows.size(), r.frames_target_chosen, r.frames_target_held,
      r.frames_following, int(r.stopped_by_command), r.boundary_error.mean_m,
      r.boundary_error.hausdorff_m, r.target_switches, r.frames_target_off, r.occlusions,
      r.max_stop_delay_frames, r.max_resume_delay_frames,
      r.odometry_accuracy ? r.odometry_accuracy->ate_unaligned.translation_m.rmse : NAN,
      r.mean_perception_ms);
  return r;
}

TEST(FollowLaser2D, ScansAreOnePlaneAcrossTheFieldOfView) {
  const auto scene = sim::make_lawn_scene(lawn_config(Scenario::kDefault), 0);
  const auto sensor = SensorModel::laser_2d();
  const sim::LidarSimulator lidar(scene, sensor);
  const auto frame = lidar.scan(0.0, [&](double) { return make_pose(1.0, 1.0, 0.45, 0, 0, 0); });
  ASSERT_GT(frame.cloud.size(), 100u);
  double min_bearing = 0, max_bearing = 0;
  for (const auto& p : frame.cloud.points) {
    EXPECT_EQ(p.ring, 0);
    EXPECT_NEAR(p.z, 0.0, 0.05);  // range noise along a level beam only
    const double b = std::atan2(p.y, p.x);
    min_bearing = std::min(min_bearing, b);
    max_bearing = std::max(max_bearing, b);
  }
  std::printf("bearings %.3f .. %.3f rad\n", min_bearing, max_bearing);
  EXPECT_GT(max_bearing, 1.7);  // returns from beside and behind the mower: wider than 180 deg
  EXPECT_LT(min_bearing, -1.7);
  EXPECT_LE(std::max(max_bearing, -min_bearing), 0.75 * M_PI + 1e-3);
  // The operator, 3 m ahead, returns about 10 points.
  ASSERT_FALSE(frame.people.empty());
  EXPECT_GE(frame.people[0].points, 8u);
}

// Measured: target chosen after 13 of 707 frames (1.3 s: the operator walks from the start),
// held in all 694 since, the lap closed by the stop command, boundary mean 0.011 m, Hausdorff
// 0.21 m, odometry ATE 0.044 m (the gyro's bias learned while the mower waited). Without the
// carried legs (LegPipeline2DConfig::held_leg_chord_max_m 0) the operator is lost for good after
// 3.5 s, when the mower lagged to 5.5 m and the classifier's first stump (5.1 m) dropped the
// legs: held in 79 of 1300 frames, like the 9 % measured on a real follow recording.
TEST(FollowLaser2D, DefaultLapHeldThroughoutAndTheSeedTargetsMet) {
  const auto r = run_2d(Scenario::kDefault);
  test::expect_seed_000_lap_targets(r);
  EXPECT_LE(r.rows.size() - r.frames_target_chosen, 20u);
  EXPECT_EQ(r.frames_target_held, r.frames_target_chosen);
  ASSERT_TRUE(r.odometry_accuracy.has_value());
  EXPECT_LT(r.odometry_accuracy->ate_unaligned.translation_m.rmse, 0.1);
}

// Scene seed 8: the operator walks off from 3 m, where the legs score just over the
// classifier's threshold and no person track holds them for a few scans. Their walking legs
// (LegPipeline2DConfig::walking_leg_travel_m) are kept out of the fast grids meanwhile.
// Measured: chosen after 13 frames and held in all 694 since, lap closed; before, the grid took
// the planted feet within two scans and the operator was chosen only ~60 s later, when the lap
// brought them back in front (held in 628 of 1294 frames).
TEST(FollowLaser2D, OperatorWalkingOffFromTheZoneEdgeIsChosenAtTheStart) {
  const auto r = run_2d(Scenario::kDefault, 8);
  test::expect_seed_000_lap_targets(r);
  EXPECT_LE(r.rows.size() - r.frames_target_chosen, 20u);
  EXPECT_EQ(r.frames_target_held, r.frames_target_chosen);
}

// 6 cm bumps: the mower and its laser pitch by up to ~5 deg, the beam meets the legs higher or
// lower and they score near the threshold. With true poses, measured: held in 635 of the 679
// frames since the target was chosen, boundary mean 0.033 m; before walking legs were kept out
// of the fast grids, 342 of 679 and 1.49 m (the operator, 3.7-4.3 m ahead, taken into the grid
// and lost).
TEST(FollowLaser2D, RoughLapHoldsTheOperatorWhoseLegsScoreNearTheThreshold) {
  const auto r = run_2d(Scenario::kRough, 0, PoseSource::kTruth);
  ASSERT_GT(r.frames_target_chosen, 600u);
  EXPECT_GE(double(r.frames_target_held), 0.9 * double(r.frames_target_chosen));
  EXPECT_LT(r.boundary_error.mean_m, 0.1);
  EXPECT_EQ(r.target_switches, 0u);
  EXPECT_EQ(r.frames_moving_too_close, 0u);
}

// The same lap with the mower's own pose: wheels and IMU (DeadReckoningPoseSource), its
// attitude from the gyro's three axes, levelled by the accelerometer while the wheels stand.
// Measured: odometry ATE 0.036 m, held in 644 of 646 frames, boundary mean 0.028 m; with the
// yaw from the gyro's z axis alone (the pitch rate times the roll read as a yaw rate on the
// bumps), ATE 0.470 m, held in 355, boundary mean 1.72 m.
TEST(FollowLaser2D, RoughLapWithWheelsAndImuKeepsItsPose) {
  const auto r = run_2d(Scenario::kRough);
  ASSERT_TRUE(r.odometry_accuracy.has_value());
  EXPECT_LT(r.odometry_accuracy->ate_unaligned.translation_m.rmse, 0.1);
  ASSERT_GT(r.frames_target_chosen, 600u);
  EXPECT_GE(double(r.frames_target_held), 0.9 * double(r.frames_target_chosen));
  EXPECT_LT(r.boundary_error.mean_m, 0.1);
  EXPECT_EQ(r.frames_moving_too_close, 0u);
}

// The detour behind the shed: the mower stops at the first frame the operator is not seen (a
// coasted report is not driven on). Measured: 5 occlusions, stop delay 1 frame; the operator
// comes back into view 5-5.6 m away, beyond the classifier's reach, and the mower does not move
// again (with true poses neither: docs/people.md); no false follow.
TEST(FollowLaser2D, OccludedOperatorStopsTheMowerWithinOneFrame) {
  const auto r = run_2d(Scenario::kOccluded);
  EXPECT_GE(r.occlusions, 1u);
  EXPECT_GE(r.max_stop_delay_frames, 0);
  EXPECT_LE(r.max_stop_delay_frames, 1);
  EXPECT_EQ(r.frames_target_off, 0u);
  EXPECT_EQ(r.target_switches, 0u);
  EXPECT_EQ(r.frames_moving_too_close, 0u);
}

// The operator stands 2 m ahead for 5 s beside two posts 1.5 m ahead (leg-like clutter); at leg
// height the posts read as a standing pair, and on scene seed 1 (as on 2, 4 and 5) they are
// reported before the operator, whose standing legs are not, and chosen. The choice stays
// provisional while neither they nor the mower move (FollowConfig::provisional_move_m): the
// operator walking off takes the target over. Measured: one switch, the posts the target for 59
// frames in which the mower stands (1.5 m from them, within the follow distance), lap closed.
// Before: the posts the target for all 3897 frames, the mower never moved.
TEST(FollowLaser2D, PostsChosenAtTheStartGiveWayToTheOperatorWalkingOff) {
  const auto r = run_2d(Scenario::kStandingStart, 1);
  EXPECT_TRUE(r.stopped_by_command);
  EXPECT_EQ(r.target_switches, 1u);
  EXPECT_LE(r.frames_target_off, 80u);
  EXPECT_EQ(r.frames_target_held, r.frames_target_chosen);
  // While the estimate is off the operator the mower stands.
  double moved_m = 0;
  for (const auto& row : r.rows)
    if (std::hypot(row.est_x - row.true_x, row.est_y - row.true_y) > 0.5)
      moved_m = std::max(moved_m, std::hypot(row.mower_x - r.rows.front().mower_x,
                                             row.mower_y - r.rows.front().mower_y));
  EXPECT_LT(moved_m, 0.05);
}

}  // namespace
}  // namespace fieldlidar::loops
