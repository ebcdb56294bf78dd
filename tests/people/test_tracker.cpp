#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>

#include "fieldlidar/people/assignment.hpp"
#include "fieldlidar/people/tracker.hpp"

namespace fieldlidar::people {
namespace {

double brute_force_best(const Eigen::MatrixXd& c) {
  // Rows <= cols: try every injective map of rows into columns.
  std::vector<int> cols(std::size_t(c.cols()));
  std::iota(cols.begin(), cols.end(), 0);
  double best = 1e300;
  do {
    double s = 0;
    for (int r = 0; r < c.rows(); ++r) s += c(r, cols[std::size_t(r)]);
    best = std::min(best, s);
  } while (std::next_permutation(cols.begin(), cols.end()));
  return best;
}

TEST(Assignment, MatchesBruteForceOnRandomMatrices) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0, 10);
  for (int trial = 0; trial < 50; ++trial) {
    const int rows = 1 + trial % 5, cols = rows + trial % 3;
    Eigen::MatrixXd c(rows, cols);
    for (int r = 0; r < rows; ++r)
      for (int k = 0; k < cols; ++k) c(r, k) = u(rng);
    const auto a = solve_assignment(c);
    double s = 0;
    std::vector<int> seen;
    for (int r = 0; r < rows; ++r) {
      ASSERT_GE(a[std::size_t(r)], 0);
      seen.push_back(a[std::size_t(r)]);
      s += c(r, a[std::size_t(r)]);
    }
    std::sort(seen.begin(), seen.end());
    EXPECT_EQ(std::unique(seen.begin(), seen.end()), seen.end());
    EXPECT_NEAR(s, brute_force_best(c), 1e-9);
  }
}

TEST(Assignment, ForbiddenEntriesStayUnassigned) {
  const double inf = std::numeric_limits<double>::infinity();
  Eigen::MatrixXd c(3, 2);
  c << 1, inf, inf, inf, 5, 2;
  const auto a = solve_assignment(c);
  EXPECT_EQ(a[0], 0);
  EXPECT_EQ(a[1], -1);
  EXPECT_EQ(a[2], 1);
  EXPECT_TRUE(solve_assignment(Eigen::MatrixXd(0, 3)).empty());
}

TEST(Kalman, PredictUsesTheSeedTransition) {
  Track t;
  t.state << 1, 2, 3, -1;
  t.covariance.setZero();
  kalman_predict(t, 0.5, 0.0);
  EXPECT_DOUBLE_EQ(t.state[0], 2.0);
  EXPECT_DOUBLE_EQ(t.state[1], 2.0);
  EXPECT_DOUBLE_EQ(t.state[2], 2.5);
  EXPECT_DOUBLE_EQ(t.state[3], -1.0);
  EXPECT_TRUE(t.covariance.isZero());
}

TEST(Kalman, UpdateWithEqualVariancesAveragesPositions) {
  Track t;
  t.state << 0, 0, 0, 0;
  t.covariance = Eigen::Vector4d(0.01, 1, 0.01, 1).asDiagonal();
  kalman_update(t, {1, -1}, 0.1);  // R = 0.01 = P_pos, gain 0.5
  EXPECT_NEAR(t.state[0], 0.5, 1e-12);
  EXPECT_NEAR(t.state[2], -0.5, 1e-12);
  EXPECT_NEAR(t.covariance(0, 0), 0.005, 1e-12);
}

TEST(Tracker, ConstantVelocityPersonIsConfirmedAndItsVelocityConverges) {
  PersonTracker tracker;
  const Eigen::Vector2d v(0.8, -0.3);
  for (int k = 0; k < 40; ++k) {
    const Eigen::Vector2d p = Eigen::Vector2d(1, 2) + v * (0.1 * k);
    const std::vector<Eigen::Vector2d> det{p};
    const auto r = tracker.update(0.1 * k, det);
    ASSERT_EQ(tracker.tracks().size(), 1u);
    EXPECT_EQ(r.track_of_detection[0], 1);
    EXPECT_EQ(tracker.tracks()[0].confirmed, k >= 2);
  }
  const auto& t = tracker.tracks()[0];
  EXPECT_NEAR((t.velocity() - v).norm(), 0, 0.01);
  EXPECT_NEAR((t.position() - (Eigen::Vector2d(1, 2) + v * 3.9)).norm(), 0, 0.01);
}

TEST(Tracker, TracksAreDeletedAfterMissingAndTentativeOnesSooner) {
  TrackerConfig cfg;
  cfg.delete_after_miss_s = 1.0;
  cfg.target_reattach_s = 2.0;  // the lost target's own track is kept as any other one
  PersonTracker tracker(cfg);
  for (int k = 0; k < 5; ++k) tracker.update(0.1 * k, std::vector<Eigen::Vector2d>{{2, 0}});
  tracker.update(0.5, std::vector<Eigen::Vector2d>{{2, 0}, {-3, 0}});  // a one-off clutter hit
  ASSERT_EQ(tracker.tracks().size(), 2u);
  ASSERT_TRUE(tracker.select_target(1));
  EXPECT_FALSE(tracker.select_target(2));  // tentative
  tracker.update(0.6, {});
  EXPECT_NE(tracker.target(), nullptr);  // coasting one frame
  tracker.update(0.7, {});
  EXPECT_EQ(tracker.target(), nullptr);
  EXPECT_TRUE(tracker.target_lost());
  tracker.update(0.8, {});
  EXPECT_EQ(tracker.tracks().size(), 1u);  // the tentative one is gone after 0.25 s
  tracker.update(1.4, {});
  EXPECT_EQ(tracker.tracks().size(), 1u);
  tracker.update(1.6, {});
  EXPECT_TRUE(tracker.tracks().empty());
}

TEST(Tracker, TargetKeepsItsIdWhenAnotherPersonCrossesNear) {
  // The target walks +x at 1 m/s, the other walks -y at 1 m/s and passes 0.45 m in front of it.
  PersonTracker tracker;
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0, 0.03);
  std::uint32_t target = 0, other = 0;
  for (int k = 0; k <= 60; ++k) {
    const double t = 0.1 * k;
    const Eigen::Vector2d a(-3 + t, 0), b(0.45, 3 - t);
    std::vector<Eigen::Vector2d> det{a + Eigen::Vector2d(noise(rng), noise(rng)),
                                     b + Eigen::Vector2d(noise(rng), noise(rng))};
    if (k % 2) std::swap(det[0], det[1]);  // detection order carries no identity
    const auto r = tracker.update(t, det);
    if (k == 5) {
      ASSERT_TRUE(tracker.select_nearest({-2.5, 0}).has_value());
      target = *tracker.target_id();
      other = target == 1 ? 2 : 1;
    }
    if (k > 5) {
      const std::size_t ia = (k % 2) ? 1 : 0;
      EXPECT_EQ(r.track_of_detection[ia], std::int64_t(target)) << "frame " << k;
      EXPECT_EQ(r.track_of_detection[1 - ia], std::int64_t(other)) << "frame " << k;
      ASSERT_NE(tracker.target(), nullptr);
      EXPECT_LT((tracker.target()->position() - a).norm(), 0.12);
    }
  }
  EXPECT_EQ(tracker.tracks().size(), 2u);
}

TEST(Tracker, TargetIsReacquiredNearItsLastPositionAfterItsTrackDied) {
  TrackerConfig cfg;
  cfg.delete_after_miss_s = 0.5;
  PersonTracker tracker(cfg);
  for (int k = 0; k < 5; ++k) tracker.update(0.1 * k, std::vector<Eigen::Vector2d>{{2, 0}});
  ASSERT_TRUE(tracker.select_target(1));
  for (int k = 5; k < 12; ++k) tracker.update(0.1 * k, {});
  EXPECT_TRUE(tracker.tracks().empty());
  EXPECT_TRUE(tracker.target_lost());
  // Walking away at 1 m/s; the clutter at (6, 6) stands still. The walker is the target again
  // once it has walked 1 m over 10 frames in a row (reacquire_min_walk_m, reacquire_min_streak).
  for (int k = 12; k < 26; ++k) {
    tracker.update(0.1 * k, std::vector<Eigen::Vector2d>{{2.3 + 0.1 * (k - 12), 0.1}, {6, 6}});
    if (k < 21) {
      EXPECT_TRUE(tracker.target_lost()) << "frame " << k;  // not yet confirmed
    }
  }
  ASSERT_NE(tracker.target(), nullptr);
  EXPECT_EQ(*tracker.target_id(), 1u);  // the id is kept
  EXPECT_NEAR(tracker.target()->position().x(), 3.6, 0.1);
}

TEST(Tracker, LostTargetIsNotTakenByClutterNorByAnotherPersonSeenBefore) {
  // The target walks +x at 1 m/s and vanishes behind an occluder at x = 0; a bystander walks
  // -y 3 m away all along; a flickering leg-like return sits at the occluder's corner, moving
  // a little (range noise along a wall). 12 s later the target walks out 6 m ahead.
  PersonTracker tracker;
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0, 0.15);
  for (int k = 0; k <= 200; ++k) {
    const double t = 0.1 * k;
    std::vector<Eigen::Vector2d> det{{-1.5, 6 - 0.5 * t}};              // the bystander
    if (k < 30) det.push_back({-3 + t, 0});                             // the target, until hidden
    if (k >= 30 && k % 3 != 0) det.push_back({0.3 + noise(rng), 0.8});  // corner clutter
    if (k >= 150) det.push_back({6 + 0.1 * (k - 150), 1.0});            // the target again
    tracker.update(t, det);
    if (k == 5) {
      ASSERT_TRUE(tracker.select_nearest({-2.5, 0}).has_value());
    }
    if (k > 31 && k < 160) {
      EXPECT_TRUE(tracker.target_lost()) << "frame " << k;
    }
  }
  ASSERT_NE(tracker.target(), nullptr);  // the walker 6 m on, 12 s later (radius capped 10 m)
  EXPECT_NEAR((tracker.target()->position() - Eigen::Vector2d(11, 1)).norm(), 0, 0.2);
}

TEST(Tracker, RetakeOnTheDetectorsWordOnlyWhileTheTargetIsLost) {
  PersonTracker tracker;
  for (int k = 0; k < 5; ++k) tracker.update(0.1 * k, std::vector<Eigen::Vector2d>{{2, 0}});
  ASSERT_TRUE(tracker.select_target(1));
  EXPECT_FALSE(tracker.retake(1));  // tracked: nothing to take back
  for (int k = 5; k < 12; ++k) tracker.update(0.1 * k, {});
  ASSERT_TRUE(tracker.target_lost());
  // The person is back 0.8 m aside, standing (reacquire() would wait for a 1 m walk).
  const auto r = tracker.update(1.2, std::vector<Eigen::Vector2d>{{2, 0.8}});
  ASSERT_GE(r.track_of_detection[0], 0);
  const auto id = std::uint32_t(r.track_of_detection[0]);
  EXPECT_FALSE(tracker.reacquire(id));
  EXPECT_FALSE(tracker.retake(99));  // no such track
  EXPECT_TRUE(tracker.retake(id));
  ASSERT_NE(tracker.target(), nullptr);
  EXPECT_EQ(*tracker.target_id(), 1u);  // the id is kept
  EXPECT_TRUE(tracker.target()->confirmed);
  EXPECT_FALSE(tracker.retake(id));  // no longer lost
  tracker.update(1.3, std::vector<Eigen::Vector2d>{{2, 0.8}});
  EXPECT_NE(tracker.target(), nullptr);
}

TEST(Tracker, RejectsTimeGoingBackwards) {
  PersonTracker tracker;
  tracker.update(1.0, {});
  EXPECT_THROW(tracker.update(0.5, {}), std::invalid_argument);
}

}  // namespace
}  // namespace fieldlidar::people
