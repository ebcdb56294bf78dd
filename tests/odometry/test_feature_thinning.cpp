// The thinning of the selected features before matching: one per cube, the first kept, in order.

#include <cmath>
#include <limits>
#include <random>
#include <set>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "fieldlidar/odometry/features.hpp"

namespace fieldlidar::odometry {
namespace {

TEST(FeatureThinning, KeepsTheFirstPointOfEachCubeInOrder) {
  std::vector<Eigen::Vector3f> pts = {
      {0.05f, 0.05f, 0.05f},   // cube (0, 0, 0): kept
      {0.15f, 0.01f, 0.19f},   // same cube: dropped
      {0.25f, 0.05f, 0.05f},   // cube (1, 0, 0): kept
      {-0.05f, 0.05f, 0.05f},  // cube (-1, 0, 0): kept (floor, not truncation)
      {-0.15f, 0.02f, 0.02f},  // same: dropped
      {0.05f, 0.05f, 0.05f},   // a repeat of the first: dropped
      {std::numeric_limits<float>::quiet_NaN(), 0.f, 0.f},  // dropped
      {0.05f, -0.05f, 0.05f},                               // cube (0, -1, 0): kept
  };
  thin_by_spacing(pts, 0.2);
  ASSERT_EQ(pts.size(), 4u);
  EXPECT_EQ(pts[0], Eigen::Vector3f(0.05f, 0.05f, 0.05f));
  EXPECT_EQ(pts[1], Eigen::Vector3f(0.25f, 0.05f, 0.05f));
  EXPECT_EQ(pts[2], Eigen::Vector3f(-0.05f, 0.05f, 0.05f));
  EXPECT_EQ(pts[3], Eigen::Vector3f(0.05f, -0.05f, 0.05f));
}

TEST(FeatureThinning, ZeroSpacingKeepsEverything) {
  std::vector<Eigen::Vector3f> pts(5, Eigen::Vector3f(1.f, 2.f, 3.f));
  thin_by_spacing(pts, 0.0);
  EXPECT_EQ(pts.size(), 5u);
}

TEST(FeatureThinning, OnePerOccupiedCubeAgainstASet) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-30.f, 30.f);
  std::vector<Eigen::Vector3f> pts;
  for (int i = 0; i < 5000; ++i) pts.emplace_back(u(rng), u(rng), 0.1f * u(rng));
  std::set<std::tuple<long, long, long>> cubes;
  std::vector<Eigen::Vector3f> want;
  for (const auto& p : pts) {
    const auto c = std::make_tuple(long(std::floor(p.x() / 0.5f)), long(std::floor(p.y() / 0.5f)),
                                   long(std::floor(p.z() / 0.5f)));
    if (cubes.insert(c).second) want.push_back(p);
  }
  thin_by_spacing(pts, 0.5);
  EXPECT_EQ(pts, want);
}

}  // namespace
}  // namespace fieldlidar::odometry
