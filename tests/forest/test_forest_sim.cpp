// Trunks and DBH on simulated forest frames (VLP-16, OS1-64) against the scene's TreeTruth.
// Seed 1 is the one the defaults were tuned on (seeds 7, 8, 9 were looked at too; 4-6, 10 and
// 15-26 for diagnosis); seeds 2, 3 and 11 are held out. Bounds sit a margin above/below the
// measured figures (printed). A detection matches within 0.3 m at 1.3 m. A tree is scored when its
// stem at 1.3 m is within 15 m, the frame holds >= 20 of its returns and at least half of its
// outline at 1.3 m is in view of the sensor: rays cast in the truth scene across its silhouette,
// every other stem, branch and shrub in the way (ScoreRule, visible_fraction in forest_eval.hpp).
// Less than half is a sliver beside an occluder, whose diameter no single view holds; the rule
// looks only at the truth and the sensor, never at what the detector flags. dbh_rmse() leaves out
// detections marked dbh_uncertain (every diameter trees.csv gives: it leaves theirs empty),
// dbh_all_rmse() takes every matched stem with those guesses; both are asserted.
#include <gtest/gtest.h>

#include "forest_eval.hpp"

namespace fieldlidar::forest::test {

TEST(ForestSim, Vlp16TunedSeed) {
  const auto s = run_frames(1, SensorModel::vlp16(), 4);
  s.print("VLP-16 seed 1 (tuned), 4 frames");
  EXPECT_GT(s.truth, 40);
  EXPECT_GE(s.recall(), 0.95);         // measured 1.000
  EXPECT_GE(s.precision(), 0.97);      // 1.000
  EXPECT_LE(s.pos_rmse(), 0.03);       // 0.021
  EXPECT_LE(s.dbh_rmse(), 0.012);      // 0.0102
  EXPECT_LE(s.dbh_all_rmse(), 0.017);  // 0.0154
  EXPECT_LE(s.uncertain, 2);           // 1
}

TEST(ForestSim, Vlp16HeldOutSeed) {
  const auto s = run_frames(2, SensorModel::vlp16(), 10);
  s.print("VLP-16 seed 2 (held out), 10 frames");
  EXPECT_GT(s.truth, 60);
  EXPECT_GE(s.recall(), 0.95);          // measured 0.977 (0.969 before the fit's step control)
  EXPECT_GE(s.precision(), 0.97);       // 0.992
  EXPECT_LE(s.pos_rmse(), 0.025);       // 0.0188
  EXPECT_LE(s.dbh_rmse(), 0.0095);      // 0.0077
  EXPECT_LE(s.dbh_all_rmse(), 0.0095);  // 0.0077
  EXPECT_LE(s.uncertain, 2);            // 0
}

TEST(ForestSim, Vlp16SecondHeldOutSeed) {
  const auto s = run_frames(3, SensorModel::vlp16(), 10);
  s.print("VLP-16 seed 3 (held out), 10 frames");
  EXPECT_GT(s.truth, 60);
  EXPECT_GE(s.recall(), 0.97);         // measured 0.994
  EXPECT_GE(s.precision(), 0.98);      // 1.000
  EXPECT_LE(s.pos_rmse(), 0.032);      // 0.0264
  EXPECT_LE(s.dbh_rmse(), 0.017);      // 0.0145
  EXPECT_LE(s.dbh_all_rmse(), 0.017);  // 0.0145
  EXPECT_LE(s.uncertain, 3);           // 0
}

TEST(ForestSim, Os1HeldOutSeed) {
  const auto s = run_frames(2, SensorModel::os1_64(), 10);
  s.print("OS1-64 seed 2 (held out), 10 frames");
  EXPECT_GT(s.truth, 60);
  EXPECT_GE(s.recall(), 0.94);     // measured 0.963
  EXPECT_GE(s.precision(), 0.97);  // 1.000
  EXPECT_LE(s.pos_rmse(), 0.022);  // 0.0176
  // 0.0139 over the 128 of 131 matched stems with a measured DBH, 0.0163 over all 131 (0.0187
  // and 0.0204 with the per-line widths' mean, before the edge fit): the 0.233 m stem at 7.8 m
  // seen as a 0.12 m sliver beside a nearer stem is no longer scored (under half its outline in
  // view), two of the three still marked uncertain are.
  EXPECT_LE(s.dbh_rmse(), 0.016);
  EXPECT_LE(s.dbh_all_rmse(), 0.018);
  EXPECT_LE(s.uncertain, 5);
}

// Held-out seed 11, OS1-64: every diameter trees.csv gives is within the target; two stems
// seen only as slivers beside a nearer stem on every line (0.319 m read 0.174 m) keep a guess
// that trees.csv leaves empty, 2.30 cm with them.
TEST(ForestSim, Os1ThirdHeldOutSeed) {
  const auto s = run_frames(11, SensorModel::os1_64(), 10);
  s.print("OS1-64 seed 11 (held out), 10 frames");
  EXPECT_GE(s.recall(), 0.94);         // measured 0.960 (0.953 before the fit's step control)
  EXPECT_GE(s.precision(), 0.98);      // 0.993 (0.979 before stumps and shrub tops were dropped)
  EXPECT_LE(s.pos_rmse(), 0.025);      // 0.0208
  EXPECT_LE(s.dbh_rmse(), 0.016);      // 0.0136
  EXPECT_LE(s.dbh_all_rmse(), 0.025);  // 0.0230
  EXPECT_LE(s.uncertain, 4);           // 2
}

// Diagnosis seed 5, VLP-16: a 0.20 m stem at 13 m whose every line within 1 m of breast height
// is cut by an occluder read 0.43 m as a guess (flagged); its lines above see both edges and
// measure it. Over every matched stem 0.0199 -> 0.0091 m, none left flagged.
TEST(ForestSim, Vlp16StemCutNearBreastHeightMeasuredAboveIt) {
  const auto s = run_frames(5, SensorModel::vlp16(), 10);
  s.print("VLP-16 seed 5, 10 frames");
  EXPECT_GE(s.recall(), 0.96);         // measured 0.983
  EXPECT_GE(s.precision(), 0.98);      // 1.000
  EXPECT_LE(s.dbh_rmse(), 0.011);      // 0.0090
  EXPECT_LE(s.dbh_all_rmse(), 0.011);  // 0.0090 (0.0199 with the guess)
  EXPECT_LE(s.uncertain, 0);           // 1 before
}

// The visibility rule on held-out VLP-16 seed 2: it leaves out the few stems seen over less
// than half their outline (133 -> 130 scored), and every scored stem had returns anyway.
TEST(ForestSim, VisibilityRuleLeavesOutSlivers) {
  ScoreRule returns_only;
  returns_only.min_visible = 0.0;
  const auto all = run_frames(2, SensorModel::vlp16(), 10, {}, false, returns_only);
  const auto visible = run_frames(2, SensorModel::vlp16(), 10);
  EXPECT_LT(visible.truth, all.truth);
  EXPECT_GE(visible.truth, int(0.95 * all.truth));
  EXPECT_LE(visible.dbh_all_rmse(), all.dbh_all_rmse());  // 0.0076 with the rule
}

}  // namespace fieldlidar::forest::test

namespace fieldlidar::forest::test {

// Reported, not a target of the issue: the nodding 2D scanner (60 planes) and the OS1-64 on a
// second held-out seed.
TEST(ForestSim, Tilting2dAndOs1SecondSeedReported) {
  const auto t = run_frames(2, SensorModel::tilting_2d(), 10);
  t.print("tilting 2D seed 2 (held out), 10 frames");
  EXPECT_GE(t.recall(), 0.87);     // measured 0.903
  EXPECT_GE(t.precision(), 0.96);  // 0.991
  EXPECT_LE(t.dbh_rmse(), 0.038);  // 0.0329
  const auto o = run_frames(3, SensorModel::os1_64(), 10);
  o.print("OS1-64 seed 3 (held out), 10 frames");
  EXPECT_GE(o.recall(), 0.95);          // measured 0.984
  EXPECT_GE(o.precision(), 0.97);       // 0.994
  EXPECT_LE(o.dbh_rmse(), 0.0155);      // 0.0131 (2 uncertain left out)
  EXPECT_LE(o.dbh_all_rmse(), 0.0155);  // 0.0132 with them
  EXPECT_LE(o.pos_rmse(), 0.035);       // 0.0283
  EXPECT_LE(o.uncertain, 4);
}

}  // namespace fieldlidar::forest::test

namespace fieldlidar::forest::test {

// Held-out seed 11, OS1-64, the frame at 12 s: a 0.101 m stem 11.7 m away, seen whole on 55
// returns (one or two a line). Its returns span a few centimetres across the line of sight, so
// the cylinder's depth is barely determined: full Gauss-Newton steps ran off to the radius
// bound and the stem was dropped as no cylinder; a fit that ends farther from the returns than
// it started is now done again with steps that bring it closer. (At 6.6 m, 21 s, the same stem
// is still lost: its start circle lies at the radius bound already.)
TEST(ForestSim, ThinStemFitDoesNotRunOff) {
  const sim::Scene scene = sim::make_forest_scene({}, 11);
  const auto motion = sim::drive_scene_route(scene, 31.0);
  const sim::LidarSimulator simulator(scene, SensorModel::os1_64());
  const auto frame = simulator.scan(12.0, motion.lidar_pose_fn()(12.0));
  const auto ground = segmentation::segment_ground(frame.cloud, SensorModel::os1_64());
  const auto result = extract_trees(frame.cloud, ground.is_ground);
  const Eigen::Vector2d stem(24.39, 24.60);
  const Tree* found = nullptr;
  for (const auto& t : result.trees)
    if (((frame.T_world_lidar_start * t.at_height(1.3)).head<2>() - stem).norm() < 0.3) found = &t;
  ASSERT_NE(found, nullptr);
  EXPECT_NEAR(found->dbh_m, 0.101, 0.03);
  EXPECT_LT(found->residual_m, 0.06);
}

}  // namespace fieldlidar::forest::test
