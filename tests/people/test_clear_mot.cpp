// CLEAR MOT scoring on hand-built sequences with known answers.

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/people/clear_mot.hpp"

namespace fieldlidar::people {
namespace {

using P = IdentifiedPoint;

P at(std::int64_t id, double x, double y) {
  return {id, Eigen::Vector2d(x, y)};
}

TEST(ClearMot, PerfectTrackingOfTwoPeople) {
  ClearMotScorer s;
  for (int f = 0; f < 3; ++f) {
    const std::vector<P> truth{at(1, f, 0), at(2, f, 2)};
    const std::vector<P> tracks{at(10, f + 0.1, 0), at(20, f, 2.1)};
    const auto c = s.add_frame(truth, tracks);
    EXPECT_EQ(c.matches, 2u);
  }
  const auto& t = s.totals();
  EXPECT_EQ(t.frames, 3u);
  EXPECT_EQ(t.truth, 6u);
  EXPECT_EQ(t.misses + t.false_positives + t.id_switches, 0u);
  EXPECT_DOUBLE_EQ(t.mota(), 1.0);
  EXPECT_NEAR(t.motp_m(), 0.1, 1e-12);
  EXPECT_DOUBLE_EQ(t.recall(), 1.0);
  EXPECT_DOUBLE_EQ(t.false_positives_per_frame(), 0.0);
}

TEST(ClearMot, AnotherTrackTakingOverAPersonIsOneIdSwitch) {
  ClearMotScorer s;
  const std::vector<P> truth{at(1, 2, 0)};
  s.add_frame(truth, std::vector<P>{at(7, 2.1, 0)});
  const auto c = s.add_frame(truth, std::vector<P>{at(8, 2.2, 0)});  // track 7 lost, 8 born
  EXPECT_EQ(c.id_switches, 1u);
  EXPECT_EQ(c.matches, 1u);
  // The new correspondence holds: no further switch.
  EXPECT_EQ(s.add_frame(truth, std::vector<P>{at(8, 2.2, 0)}).id_switches, 0u);
  EXPECT_NEAR(s.totals().mota(), 1.0 - 1.0 / 3.0, 1e-12);
  EXPECT_NEAR(s.totals().motp_m(), (0.1 + 0.2 + 0.2) / 3.0, 1e-12);
}

TEST(ClearMot, TwoTracksSwappingPeopleAreTwoIdSwitches) {
  ClearMotScorer s;
  s.add_frame(std::vector<P>{at(1, 0, 0), at(2, 0, 3)}, std::vector<P>{at(10, 0, 0), at(20, 0, 3)});
  const auto c = s.add_frame(std::vector<P>{at(1, 0, 0), at(2, 0, 3)},
                             std::vector<P>{at(10, 0, 3), at(20, 0, 0)});
  EXPECT_EQ(c.matches, 2u);
  EXPECT_EQ(c.id_switches, 2u);
  EXPECT_DOUBLE_EQ(s.totals().mota(), 0.5);
}

TEST(ClearMot, MissAndFalsePositive) {
  ClearMotScorer s;
  // Person 1 unreported (miss), a track on nothing (false positive), person 2 found.
  const auto c = s.add_frame(std::vector<P>{at(1, 1, 0), at(2, 4, 0)},
                             std::vector<P>{at(5, 1, 3), at(6, 4, 0.3)});
  EXPECT_EQ(c.misses, 1u);
  EXPECT_EQ(c.false_positives, 1u);
  EXPECT_EQ(c.matches, 1u);
  // A frame with no annotation: every track is a false positive.
  const auto d = s.add_frame({}, std::vector<P>{at(6, 4, 0.3)});
  EXPECT_EQ(d.false_positives, 1u);
  const auto& t = s.totals();
  EXPECT_EQ(t.truth, 2u);
  EXPECT_DOUBLE_EQ(t.mota(), 1.0 - 3.0 / 2.0);
  EXPECT_DOUBLE_EQ(t.recall(), 0.5);
  EXPECT_DOUBLE_EQ(t.false_positives_per_frame(), 1.0);
  EXPECT_NEAR(t.motp_m(), 0.3, 1e-12);
}

TEST(ClearMot, GateIsStrict) {
  ClearMotScorer s;  // 0.75 m
  const std::vector<P> truth{at(1, 0, 0)};
  const auto on = s.add_frame(truth, std::vector<P>{at(3, 0.75, 0)});
  EXPECT_EQ(on.matches, 0u);
  EXPECT_EQ(on.misses, 1u);
  EXPECT_EQ(on.false_positives, 1u);
  const auto inside = s.add_frame(truth, std::vector<P>{at(3, 0.7499, 0)});
  EXPECT_EQ(inside.matches, 1u);
  // A kept correspondence is dropped, too, once it reaches the gate.
  const auto out = s.add_frame(truth, std::vector<P>{at(3, 0.0, 0.75)});
  EXPECT_EQ(out.matches, 0u);
  ClearMotScorer wide({.gate_m = 1.0});
  EXPECT_EQ(wide.add_frame(truth, std::vector<P>{at(3, 0.75, 0)}).matches, 1u);
}

TEST(ClearMot, KnownCorrespondenceIsKeptOverACloserTrack) {
  ClearMotScorer s;
  const std::vector<P> truth{at(1, 0, 0)};
  s.add_frame(truth, std::vector<P>{at(4, 0.5, 0)});
  // Track 9 is closer, but track 4 still is within the gate: it keeps the person, 9 is a FP.
  const auto c = s.add_frame(truth, std::vector<P>{at(4, 0.6, 0), at(9, 0.05, 0)});
  EXPECT_EQ(c.matches, 1u);
  EXPECT_EQ(c.id_switches, 0u);
  EXPECT_EQ(c.false_positives, 1u);
  EXPECT_NEAR(c.distance_sum_m, 0.6, 1e-12);
}

TEST(ClearMot, CorrespondenceSurvivesFramesWithoutTheTrack) {
  ClearMotScorer s;
  const std::vector<P> truth{at(1, 0, 0)};
  s.add_frame(truth, std::vector<P>{at(4, 0.1, 0)});
  EXPECT_EQ(s.add_frame(truth, {}).misses, 1u);
  // The same track back after a gap: not a switch (the last known correspondence holds).
  EXPECT_EQ(s.add_frame(truth, std::vector<P>{at(4, 0.1, 0)}).id_switches, 0u);
}

TEST(ClearMot, TrackMovingToANewPersonCountsAsTheBenchmarkDoes) {
  const std::vector<P> a{at(1, 0, 0)}, b{at(2, 5, 0)};
  const std::vector<P> track_at_a{at(4, 0.1, 0)}, track_at_b{at(4, 5.1, 0)};
  ClearMotScorer benchmark;
  benchmark.add_frame(a, track_at_a);
  EXPECT_EQ(benchmark.add_frame(b, track_at_b).id_switches, 1u);
  ClearMotScorer paper({.count_track_side_switches = false});
  paper.add_frame(a, track_at_a);
  EXPECT_EQ(paper.add_frame(b, track_at_b).id_switches, 0u);
}

TEST(ClearMot, HungarianMinimisesTotalDistance) {
  ClearMotScorer s;
  // Greedy (closest pair first) would take (10, 1) at 0.1 and leave 2 unmatched; the assignment
  // matches both.
  const auto c = s.add_frame(std::vector<P>{at(1, 0, 0), at(2, 0.6, 0)},
                             std::vector<P>{at(10, 0.1, 0), at(20, -0.5, 0)});
  EXPECT_EQ(c.matches, 2u);
  EXPECT_NEAR(c.distance_sum_m, 0.5 + 0.5, 1e-12);
}

TEST(ClearMot, RejectsRepeatedIdsAndBadGate) {
  ClearMotScorer s;
  EXPECT_THROW(s.add_frame(std::vector<P>{at(1, 0, 0), at(1, 1, 0)}, {}), Error);
  EXPECT_THROW(s.add_frame({}, std::vector<P>{at(3, 0, 0), at(3, 1, 0)}), Error);
  EXPECT_THROW(s.add_frame(std::vector<P>{at(1, NAN, 0)}, {}), Error);
  EXPECT_THROW(ClearMotScorer({.gate_m = 0.0}), Error);
}

}  // namespace
}  // namespace fieldlidar::people
