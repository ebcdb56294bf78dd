// Trunks and DBH on simulated forest frames (VLP-16, OS1-64) against the scene's TreeTruth.
// Seed 1 is the one the defaults were tuned on; seed 2 is held out. Bounds sit a margin below
// the measured figures (printed), which are far from the targets for DBH (2 cm RMSE) and
// for the OS1-64's recall.
#include <gtest/gtest.h>

#include "forest_eval.hpp"

namespace fieldlidar::forest::test {

TEST(ForestSim, Vlp16TunedSeed) {
  const auto s = run_frames(1, SensorModel::vlp16(), 4);
  s.print("VLP-16 seed 1 (tuned), 4 frames");
  EXPECT_GT(s.truth, 40);
  EXPECT_GE(s.recall(), 0.85);
  EXPECT_GE(s.precision(), 0.95);
  EXPECT_LE(s.pos_rmse(), 0.09);
  EXPECT_LE(s.dbh_rmse(), 0.12);
}

TEST(ForestSim, Vlp16HeldOutSeed) {
  const auto s = run_frames(2, SensorModel::vlp16(), 10);
  s.print("VLP-16 seed 2 (held out), 10 frames");
  EXPECT_GT(s.truth, 60);
  EXPECT_GE(s.recall(), 0.80);
  EXPECT_GE(s.precision(), 0.90);
  EXPECT_LE(s.pos_rmse(), 0.10);
  EXPECT_LE(s.dbh_rmse(), 0.12);
}

TEST(ForestSim, Os1HeldOutSeed) {
  const auto s = run_frames(2, SensorModel::os1_64(), 10);
  s.print("OS1-64 seed 2 (held out), 10 frames");
  EXPECT_GT(s.truth, 60);
  EXPECT_GE(s.recall(), 0.45);  // measured 0.511: far below the VLP-16, not understood yet
  EXPECT_GE(s.precision(), 0.90);
  EXPECT_LE(s.pos_rmse(), 0.10);
  EXPECT_LE(s.dbh_rmse(), 0.12);
}

}  // namespace fieldlidar::forest::test
