// Trunks and DBH on simulated forest frames (VLP-16, OS1-64) against the scene's TreeTruth.
// Seed 1 is the one the defaults were tuned on (seeds 7, 8, 9 were looked at too); seeds 2 and 3
// are held out. Bounds sit a margin below the measured figures (printed). A detection matches
// within 0.3 m at 1.3 m; a tree is scored when its stem at 1.3 m is within 15 m and the frame
// holds >= 20 of its returns. DBH figures leave out detections marked dbh_uncertain (a stem seen
// only as a sliver beside an occluder on every line), whose count is asserted.
#include <gtest/gtest.h>

#include "forest_eval.hpp"

namespace fieldlidar::forest::test {

TEST(ForestSim, Vlp16TunedSeed) {
  const auto s = run_frames(1, SensorModel::vlp16(), 4);
  s.print("VLP-16 seed 1 (tuned), 4 frames");
  EXPECT_GT(s.truth, 40);
  EXPECT_GE(s.recall(), 0.95);  // measured 0.979
  EXPECT_GE(s.precision(), 0.97);
  EXPECT_LE(s.pos_rmse(), 0.03);   // 0.021
  EXPECT_LE(s.dbh_rmse(), 0.015);  // 0.0115
  EXPECT_LE(s.uncertain, 2);       // 1
}

TEST(ForestSim, Vlp16HeldOutSeed) {
  const auto s = run_frames(2, SensorModel::vlp16(), 10);
  s.print("VLP-16 seed 2 (held out), 10 frames");
  EXPECT_GT(s.truth, 60);
  EXPECT_GE(s.recall(), 0.93);     // measured 0.962
  EXPECT_GE(s.precision(), 0.96);  // 0.992
  EXPECT_LE(s.pos_rmse(), 0.03);   // 0.019
  EXPECT_LE(s.dbh_rmse(), 0.019);  // 0.0170
  EXPECT_LE(s.uncertain, 3);       // 1
}

TEST(ForestSim, Vlp16SecondHeldOutSeed) {
  const auto s = run_frames(3, SensorModel::vlp16(), 10);
  s.print("VLP-16 seed 3 (held out), 10 frames");
  EXPECT_GT(s.truth, 60);
  EXPECT_GE(s.recall(), 0.97);     // measured 0.995
  EXPECT_GE(s.precision(), 0.98);  // 1.000
  EXPECT_LE(s.pos_rmse(), 0.035);  // 0.0267
  EXPECT_LE(s.dbh_rmse(), 0.018);  // 0.0157
  EXPECT_LE(s.uncertain, 5);       // 3
}

TEST(ForestSim, Os1HeldOutSeed) {
  const auto s = run_frames(2, SensorModel::os1_64(), 10);
  s.print("OS1-64 seed 2 (held out), 10 frames");
  EXPECT_GT(s.truth, 60);
  EXPECT_GE(s.recall(), 0.93);     // measured 0.957
  EXPECT_GE(s.precision(), 0.97);  // 1.000
  EXPECT_LE(s.pos_rmse(), 0.04);   // 0.031
  // 0.0190 over the 129 of 135 matched stems with a measured DBH. The 6 marked uncertain
  // include the 0.233 m stem at 7.8 m seen as a 0.12 m sliver beside a nearer stem; with them
  // the RMSE is 0.033.
  EXPECT_LE(s.dbh_rmse(), 0.020);
  EXPECT_LE(s.uncertain, 8);
}

}  // namespace fieldlidar::forest::test

namespace fieldlidar::forest::test {

// Reported, not a target of the issue: the nodding 2D scanner (60 planes) and the OS1-64 on a
// second held-out seed.
TEST(ForestSim, Tilting2dAndOs1SecondSeedReported) {
  const auto t = run_frames(2, SensorModel::tilting_2d(), 10);
  t.print("tilting 2D seed 2 (held out), 10 frames");
  EXPECT_GE(t.recall(), 0.85);     // measured 0.883
  EXPECT_GE(t.precision(), 0.96);  // 0.991
  EXPECT_LE(t.dbh_rmse(), 0.038);  // 0.0337
  const auto o = run_frames(3, SensorModel::os1_64(), 10);
  o.print("OS1-64 seed 3 (held out), 10 frames");
  EXPECT_GE(o.recall(), 0.94);     // measured 0.968
  EXPECT_GE(o.precision(), 0.97);  // 0.995
  EXPECT_LE(o.dbh_rmse(), 0.019);  // 0.0169 (4 uncertain left out; 0.0177 with them)
  EXPECT_LE(o.pos_rmse(), 0.04);   // 0.029
  EXPECT_LE(o.uncertain, 6);
}

}  // namespace fieldlidar::forest::test
