// JointPersonTracker on leg observations built in code (the same input the 3D path's legs give):
// a person standing in the follow zone, then walking off; one leg hidden behind the other; a
// post on occupied space; a pair of legs standing far from the zone.

#include <gtest/gtest.h>

#include <set>
#include <vector>

#include "fieldlidar/people/joint_person_tracker.hpp"

namespace fieldlidar::people {
namespace {

std::vector<LegObservation> two_legs(const Eigen::Vector2d& body, double phase, double score = 1) {
  return {{body + Eigen::Vector2d(0.12 * phase, 0.14), score},
          {body + Eigen::Vector2d(-0.12 * phase, -0.14), score}};
}

// The operator stands 1.8 m in front of the sensor for 5 s at 10 Hz, then walks off ahead: the
// track is reported while standing (the target can be chosen before the first step) and keeps
// its id for the whole walk, also through scans where one leg hides the other.
TEST(JointPersonTracker, StandingThenWalkingOperatorIsReportedBeforeTheFirstStep) {
  JointPersonTracker tracker;
  std::set<std::uint32_t> ids;
  int first_report = -1, reported_walking = 0, walking_scans = 0;
  for (int k = 0; k < 100; ++k) {
    const double t = 0.1 * k;
    const bool walking = k >= 50;
    const Eigen::Vector2d body(1.8 + (walking ? 0.1 * (k - 50) : 0.0), 0.0);
    auto legs = two_legs(body, walking ? ((k % 6) - 2.5) / 2.5 : 0.2);
    if (walking && k % 6 == 0) legs.pop_back();  // one leg behind the other
    const auto upd = tracker.update(t, legs, Eigen::Isometry2d::Identity());
    walking_scans += walking;
    for (const auto id : upd.reported) {
      ids.insert(id);
      if (first_report < 0) first_report = k;
      if (walking) {
        ++reported_walking;
        EXPECT_LT((tracker.find(id)->position() - body).norm(), 0.3);
      }
    }
  }
  EXPECT_GE(first_report, 0);
  EXPECT_LE(first_report, 8);  // under a second standing
  EXPECT_EQ(reported_walking, walking_scans);
  EXPECT_EQ(ids.size(), 1u);
}

TEST(JointPersonTracker, OneLegAloneKeepsTheTrack) {
  JointPersonTracker tracker;
  for (int k = 0; k < 10; ++k)
    tracker.update(0.1 * k, two_legs({2.0, 1.0}, 0.2), Eigen::Isometry2d::Identity());
  ASSERT_EQ(tracker.tracks().size(), 1u);
  const auto id = tracker.tracks()[0].id;
  for (int k = 10; k < 20; ++k) {
    const std::vector<LegObservation> one{{{2.0 + 0.12, 1.14}, 1.0}};
    const auto upd = tracker.update(0.1 * k, one, Eigen::Isometry2d::Identity());
    ASSERT_EQ(upd.reported.size(), 1u);
    EXPECT_EQ(upd.reported[0], id);
    EXPECT_EQ(upd.person_of_leg[0], std::int64_t(id));
  }
}

// A leg-shaped post stands on cells the occupancy grid has seen occupied for many scans: no
// track is born there.
TEST(JointPersonTracker, NoTrackOnOccupiedSpace) {
  StaticBackgroundConfig gc;
  gc.warmup_scans = 3;
  gc.rate = 0.15;
  gc.static_occupancy = 0.2;
  StaticBackground grid(gc);
  const std::vector<Eigen::Vector2d> post{{3.0, 0.0}, {3.0, 0.3}};
  for (int k = 0; k < 10; ++k) grid.update(post);
  JointPersonTracker tracker;
  for (int k = 0; k < 20; ++k) {
    const std::vector<LegObservation> legs{{post[0], 2.0}, {post[1], 2.0}};
    const auto upd = tracker.update(0.1 * k, legs, Eigen::Isometry2d::Identity(), &grid);
    EXPECT_TRUE(upd.reported.empty());
  }
  EXPECT_TRUE(tracker.tracks().empty());
}

// A reported person whose cells become occupied (they stood long beside something static) is
// dropped after occupied_max_scans scans, unless a leg scoring at least occupied_keep_score
// updates them in that scan.
TEST(JointPersonTracker, SureLegsKeepAReportedPersonOnOccupiedSpace) {
  StaticBackgroundConfig gc;
  gc.warmup_scans = 3;
  gc.rate = 0.15;
  gc.static_occupancy = 0.2;
  for (const double leg_score : {1.0, 3.5}) {
    JointTrackerConfig jc;
    jc.occupied_keep_score = 3.0;
    JointPersonTracker tracker(jc);
    StaticBackground grid(gc);
    const Eigen::Vector2d body(1.5, 0.0);
    for (int k = 0; k < 10; ++k)  // reported while standing, on free cells
      tracker.update(0.1 * k, two_legs(body, 0.2, 2.0), Eigen::Isometry2d::Identity(), &grid);
    ASSERT_EQ(tracker.tracks().size(), 1u);
    ASSERT_TRUE(tracker.tracks()[0].reported);
    const std::vector<Eigen::Vector2d> cells{body, body + Eigen::Vector2d(0.12, 0.14),
                                             body - Eigen::Vector2d(0.12, 0.14)};
    for (int k = 0; k < 10; ++k) grid.update(cells);
    for (int k = 10; k < 20; ++k)
      tracker.update(0.1 * k, two_legs(body, 0.2, leg_score), Eigen::Isometry2d::Identity(), &grid);
    EXPECT_EQ(tracker.tracks().size(), leg_score >= 3.0 ? 1u : 0u) << "leg score " << leg_score;
  }
}

// Weak legs (scores below the classifier threshold) never build a person.
TEST(JointPersonTracker, WeakLegsAreNoPerson) {
  JointPersonTracker tracker;
  for (int k = 0; k < 30; ++k)
    EXPECT_TRUE(
        tracker.update(0.1 * k, two_legs({2.0, 0.0}, 0.2, -0.5), Eigen::Isometry2d::Identity())
            .reported.empty());
}

// A pair that stands still is reported on its paired detections only when it has a standing
// person's shape: legs no wider than a leg, feet no farther apart than a shoulder's width. Two
// wide blobs (bins, boxes) or two legs 0.55 m apart (a chair's) stay unreported, with the same
// scores and as many pairs.
TEST(JointPersonTracker, StandingPairsNeedAPersonsShape) {
  auto reported_scans = [](double half_gap_m, double width_m) {
    JointTrackerConfig c;
    c.strong_evidence = 1e9;  // paired detections only
    JointPersonTracker tracker(c);
    int reported = 0;
    for (int k = 0; k < 20; ++k) {
      const std::vector<LegObservation> legs{{{4.0, half_gap_m}, 1.0, width_m},
                                             {{4.0, -half_gap_m}, 1.0, width_m}};
      reported += !tracker.update(0.1 * k, legs, Eigen::Isometry2d::Identity()).reported.empty();
      if (k == 19) {
        EXPECT_EQ(tracker.tracks().size(), 1u);
        if (!tracker.tracks().empty()) {
          EXPECT_EQ(tracker.tracks()[0].pair_hits, 20);
        }
      }
    }
    return reported;
  };
  EXPECT_GE(reported_scans(0.14, 0.10), 16);  // a person: 0.28 m between the legs
  EXPECT_GE(reported_scans(0.14, 0.0), 16);   // widths unknown (0) pass
  EXPECT_EQ(reported_scans(0.14, 0.30), 0);   // wider than a leg
  EXPECT_EQ(reported_scans(0.275, 0.10), 0);  // 0.55 m apart
}

TEST(JointPersonTracker, TimeMustNotGoBack) {
  JointPersonTracker tracker;
  tracker.update(1.0, {}, Eigen::Isometry2d::Identity());
  EXPECT_THROW(tracker.update(0.5, {}, Eigen::Isometry2d::Identity()), std::invalid_argument);
}

}  // namespace
}  // namespace fieldlidar::people

namespace fieldlidar::people {
namespace {

std::vector<LegObservation> carried(std::vector<LegObservation> legs) {
  for (auto& l : legs) {
    l.score = 0;
    l.carry_only = true;
  }
  return legs;
}

// Carried legs (leg-sized segments the classifier did not take, near a reported person: a person
// followed beyond the classifier's reach) keep a reported person walking away, for at most
// carried_max_s; they never give birth to a track nor update one not yet reported.
TEST(JointPersonTracker, CarriedLegsHoldOnlyAReportedPersonAndOnlyForAWhile) {
  JointTrackerConfig cfg;
  cfg.carried_max_s = 2.0;
  JointPersonTracker tracker(cfg);
  const Eigen::Isometry2d still = Eigen::Isometry2d::Identity();
  // Walks off at 1 m/s: scored legs for 2 s (reported), then carried legs only.
  std::uint32_t id = 0;
  double t = 0;
  for (int k = 0; k < 20; ++k, t += 0.1) {
    const auto upd =
        tracker.update(t, two_legs({2.0 + 0.1 * k, 0.0}, ((k % 6) - 2.5) / 2.5), still);
    if (!upd.reported.empty()) id = upd.reported[0];
  }
  ASSERT_NE(id, 0u);
  int held = 0;
  for (int k = 20; k < 60; ++k, t += 0.1) {
    const Eigen::Vector2d body(2.0 + 0.1 * k, 0.0);
    const auto upd = tracker.update(t, carried(two_legs(body, ((k % 6) - 2.5) / 2.5)), still);
    const JointTrack* track = tracker.find(id);
    if (!track) break;
    ++held;
    EXPECT_LT((track->position() - body).norm(), 0.25) << k;  // it follows the carried legs
    EXPECT_EQ(tracker.tracks().size(), 1u);                   // and they give no other track
    EXPECT_EQ(upd.reported.size(), 1u);
  }
  EXPECT_GE(held, 19);  // carried_max_s (2 s) and no longer
  EXPECT_LE(held, 21);
  EXPECT_EQ(tracker.find(id), nullptr);

  // Carried legs alone: no track.
  JointPersonTracker fresh(cfg);
  for (int k = 0; k < 30; ++k) fresh.update(0.1 * k, carried(two_legs({3.0, 1.0}, 0.2)), still);
  EXPECT_TRUE(fresh.tracks().empty());
}

}  // namespace
}  // namespace fieldlidar::people
