#include <gtest/gtest.h>

#include "fieldlidar/core/trajectory_match.hpp"

using namespace fieldlidar;

TEST(TrajectoryMatch, PairsNearestStampsWithinTheTolerance) {
  Trajectory a, b;
  for (int i = 0; i < 10; ++i) a.push_back(0.1 * i, make_pose(i, 0, 0, 0, 0, 0));
  // b: 10 Hz shifted by 3 ms, a missing stamp (0.4 s) and an extra one (0.45 s) far from any of a.
  for (int i = 0; i < 10; ++i) {
    if (i == 4) {
      b.push_back(0.45, make_pose(100, 0, 0, 0, 0, 0));
      continue;
    }
    b.push_back(0.1 * i + 0.003, make_pose(i, 1, 0, 0, 0, 0));
  }
  const MatchedPoses m = match_by_time(a, b, 0.01);
  ASSERT_EQ(m.indices.size(), 9u);
  for (const auto& [i, j] : m.indices) {
    EXPECT_EQ(i, j);
    EXPECT_NE(i, 4u);
  }
  for (std::size_t k = 0; k < m.a.size(); ++k)
    EXPECT_DOUBLE_EQ(m.a[k].translation().x(), m.b[k].translation().x());
  EXPECT_NEAR(m.max_dt_s, 0.003, 1e-12);
  EXPECT_TRUE(match_by_time(a, b, 0.001).indices.empty());
}

TEST(TrajectoryMatch, UsesEachPoseOnce) {
  Trajectory a, b;
  a.push_back(1.0, Pose::Identity());
  a.push_back(1.004, Pose::Identity());
  b.push_back(1.003, Pose::Identity());
  const MatchedPoses m = match_by_time(a, b, 0.01);
  ASSERT_EQ(m.indices.size(), 1u);
  EXPECT_EQ(m.indices[0], (std::pair<std::size_t, std::size_t>{0, 0}));
}
