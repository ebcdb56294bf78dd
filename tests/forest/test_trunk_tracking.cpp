// Association of trunk landmarks by pair consistency and the 6-DoF motion from axes and ground.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "fieldlidar/forest/tracking.hpp"

namespace fieldlidar::forest {
namespace {

std::vector<TrunkLandmark> stand(int n, std::mt19937& rng) {
  std::uniform_real_distribution<double> xy(-12, 12), dbh(0.1, 0.5), lean(-0.1, 0.1);
  std::vector<TrunkLandmark> out;
  for (int i = 0; i < n; ++i)
    out.push_back(
        {{xy(rng), xy(rng), 0.4}, Eigen::Vector3d(lean(rng), lean(rng), 1).normalized(), dbh(rng)});
  return out;
}

Pose motion(double yaw, double roll, double x, double y, double z) {
  Pose T = Pose::Identity();
  T.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  T.translation() = Eigen::Vector3d(x, y, z);
  return T;
}

// The reference stand seen from a moved sensor, with noise, two trees lost and two new ones.
std::vector<TrunkLandmark> seen_from(const std::vector<TrunkLandmark>& ref, const Pose& T,
                                     std::mt19937& rng) {
  std::normal_distribution<double> g(0, 0.02);
  std::vector<TrunkLandmark> cur;
  const Pose inv = T.inverse();
  for (std::size_t i = 2; i < ref.size(); ++i)
    cur.push_back({inv * ref[i].point + Eigen::Vector3d(g(rng), g(rng), 0),
                   inv.linear() * ref[i].axis, ref[i].dbh_m + g(rng) * 0.5});
  cur.push_back({{3.0, -4.0, 0.3}, Eigen::Vector3d::UnitZ(), 0.3});
  cur.push_back({{-6.0, 2.0, 0.3}, Eigen::Vector3d::UnitZ(), 0.2});
  return cur;
}

TEST(TrunkTracking, PairConsistencyFindsTheRightMatches) {
  std::mt19937 rng(5);
  const auto ref = stand(20, rng);
  const Pose T = motion(0.05, 0.0, 0.4, -0.2, 0.0);
  const auto cur = seen_from(ref, T, rng);
  AssociationConfig cfg;
  cfg.gate_m = 1.0;
  const auto m = associate_trunks(ref, cur, Pose::Identity(), cfg);  // prior 0.5 m / 3 deg off
  int right = 0;
  for (const auto& [i, j] : m) right += (i == j + 2);
  EXPECT_GE(m.size(), 15u);
  EXPECT_EQ(right, int(m.size()));
}

TEST(TrunkTracking, MotionFromAxesAndGround) {
  std::mt19937 rng(6);
  const auto ref = stand(15, rng);
  const Pose T = motion(0.08, 0.02, 0.5, 0.1, 0.03);
  const auto cur = seen_from(ref, T, rng);
  std::vector<std::pair<std::size_t, std::size_t>> matches;
  for (std::size_t j = 0; j + 2 < cur.size(); ++j) matches.emplace_back(j + 2, j);
  const GroundPlane g_ref{Eigen::Vector3d::UnitZ(), 0.9, true};
  const Eigen::Vector3d n = T.linear().transpose() * g_ref.normal;  // the same ground, seen moved
  const GroundPlane g_cur{n, g_ref.offset + g_ref.normal.dot(T.translation()), true};
  const Pose est = estimate_trunk_motion(ref, cur, matches, g_ref, g_cur, Pose::Identity());
  EXPECT_LT((est.translation() - T.translation()).norm(), 0.02);
  EXPECT_LT(Eigen::AngleAxisd(est.linear().transpose() * T.linear()).angle(), 0.005);
}

TEST(TrunkTracking, NoTreesKeepsThePrediction) {
  PointCloud empty;
  TrunkTracker tracker;
  const auto r0 = tracker.track(empty, {});
  EXPECT_FALSE(r0.tracked);
  const auto r1 = tracker.track(empty, {}, motion(0, 0, 1.0, 0, 0));
  EXPECT_FALSE(r1.tracked);
  EXPECT_NEAR(r1.T_world_lidar.translation().x(), 1.0, 1e-9);
  EXPECT_TRUE(tracker.map().empty());
}

}  // namespace
}  // namespace fieldlidar::forest
