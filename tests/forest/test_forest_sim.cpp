// Trunks and DBH on simulated forest frames (VLP-16, OS1-64) against the scene's TreeTruth.
#include <gtest/gtest.h>

#include "forest_eval.hpp"

namespace fieldlidar::forest::test {

TEST(ForestSim, Vlp16Tune) {
  const auto s = run_frames(1, SensorModel::vlp16(), 4, {}, true);
  s.print("VLP-16 seed 1");
  EXPECT_GT(s.truth, 10);
}

TEST(ForestSim, Os1Tune) {
  const auto s = run_frames(1, SensorModel::os1_64(), 4, {}, true);
  s.print("OS1-64 seed 1");
  EXPECT_GT(s.truth, 10);
}

}  // namespace fieldlidar::forest::test
