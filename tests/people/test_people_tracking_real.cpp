// People tracking with the shipped 2D config (config/legs_2d.yaml and its classifier) on the real
// recordings of ../shared/data:
// - general_tracking_moving_1.bag (a moving robot, 12 annotated people, the leg_tracker
//   benchmark's scorer: bearings -80..12 deg, 0.75 m gate). The tracker's settings were chosen on
//   scans 0-436 (which hold all 133 scored annotations); scans 437-872 hold none and were not
//   looked at while tuning: there only false persons can be counted.
// - negative_2.bag (no people; three scan topics): false persons and false legs per scan.
// - positive_1..4 (annotated legs in a wedge): leg recall. The shipped classifier was trained on
//   these bags, so these recalls are not held out (test_legs_classifier_real.cpp holds them out).

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <memory>
#include <sstream>

#include "fieldlidar/people/clear_mot.hpp"
#include "fieldlidar/people/legs_2d_pipeline.hpp"
#include "legs_data.hpp"
#include "shipped_legs_2d.hpp"

namespace fieldlidar::people {
namespace {

LegPipeline2DConfig shipped() {
  return test::shipped_legs_2d();
}

struct TrackingScores {
  ClearMotCounts tuned, held_out, whole;
};

TrackingScores score_tracking_bag(const LegPipeline2DConfig& config) {
  const auto bag = test::data_file("legs_2d_tracking/general_tracking_moving_1.bag");
  const auto truth = io::read_person_annotations(bag, "/scan", "/ground_truth_people_tracks");
  io::SourceOptions so;
  so.topic = "/scan";
  auto src = io::FrameSource::open(bag, so);
  LegPipeline2D pipeline(config);
  ClearMotScorer tuned, held_out, whole;
  auto wedge = [](const Eigen::Vector2d& p) { return in_bearing_wedge(p, -80, 12, 1e9); };
  while (auto f = src->next()) {
    const auto out = pipeline.process(f->stamp_s, scan_points_2d(f->cloud));
    std::vector<IdentifiedPoint> gt, tracked;
    for (const auto& a : truth.at(f->index).people) {
      const Eigen::Vector2d p(a.pose.translation().x(), a.pose.translation().y());
      if (wedge(p)) gt.push_back({a.id, p});
    }
    for (const auto& p : out.people)
      if (wedge(p.position_m)) tracked.push_back({p.track, p.position_m});
    (f->index <= 436 ? tuned : held_out).add_frame(gt, tracked);
    whole.add_frame(gt, tracked);
  }
  return {tuned.totals(), held_out.totals(), whole.totals()};
}

void print(const char* name, const ClearMotCounts& c) {
  std::printf(
      "%-22s scans %zu truth %zu matches %zu misses %zu false persons %zu (%.4f/scan) id "
      "switches %zu MOTA %.3f recall %.3f MOTP %.3f m\n",
      name, c.frames, c.truth, c.matches, c.misses, c.false_positives,
      c.false_positives_per_frame(), c.id_switches, c.mota(), c.truth ? c.recall() : 0.0,
      c.matches ? c.motp_m() : 0.0);
}

void print(const TrackingScores& s) {
  print("scans 0-436 (tuned)", s.tuned);
  print("scans 437-872", s.held_out);
  print("whole bag", s.whole);
}

// The shipped settings. Measured: scans 0-436 45 of 133 matched, 7 false persons (0.016 per
// scan), 0 id switches, MOTA 0.286, recall 0.338, MOTP 0.078 m; scans 437-872 8 false persons
// (0.018 per scan). Before reported persons were also updated by carried legs (leg-sized
// segments the classifier did not take, near them: LegPipeline2DConfig::held_leg_chord_max_m):
// 43 matched, MOTA 0.271, MOTP 0.111 m, the same false persons. Before leg-sized blobs the
// classifier cannot judge (fewer than 6 returns and wider than 2 cm, or beyond 5 m) were kept out
// of the person grid (unjudged_occupancy_weight) and a reported person's own returns out of the
// grids while no leg updated it (held_person_radius_m): 2 matched, 1 false person, MOTA 0.008; the
// standing people the robot drives towards had filled the grid as 1-5-point blobs at 5-8 m before
// their legs scored as legs. With those and a tentative track's 0.35 s to live: 39 matched, MOTA
// 0.248.
TEST(PeopleTrackingReal, MovingRobotBenchmarkBag) {
  FIELDLIDAR_REQUIRE_DATA("legs_2d_tracking/general_tracking_moving_1.bag");
  const auto s = score_tracking_bag(shipped());
  print(s);
  EXPECT_EQ(s.whole.truth, 133u);
  EXPECT_EQ(s.tuned.truth, 133u);
  EXPECT_GE(s.tuned.matches, 45u);
  EXPECT_GE(s.tuned.mota(), 0.28);
  EXPECT_LE(s.tuned.false_positives, 8u);
  EXPECT_LT(s.tuned.motp_m(), 0.09);
  EXPECT_EQ(s.whole.id_switches, 0u);
  EXPECT_LE(s.held_out.false_positives, 10u);
}

// Leg-sized returns kept out of the occupancy grid (compact_occupancy_weight 0): standing
// people are tracked while the robot drives past them, and so is furniture (negative_2.bag: 0.17
// / 0.22 / 0.12 false persons per scan). Measured: scans 0-436 39 of 133 matched, 8 false
// persons, 0 id switches, MOTA 0.233, recall 0.293, MOTP 0.106 m; scans 437-872 9 false persons
// (43 matched, MOTA 0.256, 9 and 8 false persons with the 2D pipeline's standing_pair_hits 4
// and tentative_max_miss_s 0.45). Since the follow zone does not teach the sensor-frame grid
// while the robot turns slowly (LegPipeline2DConfig::zone_turn_rate_max_deg_s): 45 matched, 8
// false persons, MOTA 0.278, MOTP 0.078 m; scans 437-872 12 false persons (8 with the zone
// learned there too), 14 since walking legs stay out of the fast grids
// (LegPipeline2DConfig::walking_leg_travel_m: without the compact blobs the world grid holds,
// the sensor-frame grid is what takes furniture while the robot stands).
TEST(PeopleTrackingReal, MovingRobotBenchmarkBagStandingPeopleKept) {
  FIELDLIDAR_REQUIRE_DATA("legs_2d_tracking/general_tracking_moving_1.bag");
  auto config = shipped();
  config.compact_occupancy_weight = 0.0;
  const auto s = score_tracking_bag(config);
  print(s);
  EXPECT_GE(s.tuned.matches, 37u);
  EXPECT_GE(s.tuned.mota(), 0.22);
  EXPECT_LE(s.tuned.false_positives, 10u);
  EXPECT_EQ(s.whole.id_switches, 0u);
  EXPECT_LT(s.tuned.motp_m(), 0.12);
  EXPECT_LE(s.held_out.false_positives, 15u);
}

// Measured: false persons per scan 0 / 0 / 0 (0 / 0 / 0.028 before standing pairs needed a
// person's shape, JointTrackerConfig::standing_leg_width_max_m: one 12-scan track on
// /right_scan of two 0.2-0.35 m wide blobs 0.5 m apart); false legs per scan 0.561 / 0.915 /
// 0.694 (3.17 / 4.33 / 3.51 before legs on occupied space needed a sure score or track
// evidence, occupied_leg_score_min).
TEST(PeopleTrackingReal, PeopleFreeBag) {
  FIELDLIDAR_REQUIRE_DATA("legs_2d/negative_2.bag");
  const double max_false_persons[] = {0.005, 0.005, 0.005};
  int i = 0;
  for (const char* topic : {"/left_scan", "/rear_scan", "/right_scan"}) {
    const auto scans = test::load_leg_scans("legs_2d/negative_2.bag", topic, "");
    LegPipeline2D pipeline(shipped());
    std::size_t persons = 0, legs = 0;
    for (const auto& s : scans) {
      const auto out = pipeline.process(s.stamp_s, s.points);
      persons += out.people.size();
      legs += out.legs.size();
    }
    const double per_scan = double(persons) / double(scans.size());
    std::printf("%s: %zu scans, false persons/scan %.4f, false legs/scan %.3f\n", topic,
                scans.size(), per_scan, double(legs) / double(scans.size()));
    EXPECT_LE(per_scan, max_false_persons[i++]) << topic;
    EXPECT_LE(double(legs) / double(scans.size()), 1.0) << topic;
  }
  // Legs reported only with a margin over the classifier's threshold or leg-track evidence
  // (1 / 1) as well: measured 0.393 false legs per scan on /left_scan (1.94 without the rule for
  // occupied space), persons unchanged.
  auto config = shipped();
  config.leg_report_margin = 1.0;
  config.leg_report_evidence = 1.0;
  LegPipeline2D pipeline(config);
  const auto scans = test::load_leg_scans("legs_2d/negative_2.bag", "/left_scan", "");
  std::size_t persons = 0, legs = 0;
  for (const auto& s : scans) {
    const auto out = pipeline.process(s.stamp_s, s.points);
    persons += out.people.size();
    legs += out.legs.size();
  }
  std::printf("/left_scan, legs with margin 1 / evidence 1: false legs/scan %.3f\n",
              double(legs) / double(scans.size()));
  EXPECT_LE(double(legs) / double(scans.size()), 0.45);
  EXPECT_EQ(persons, 0u);
}

// Measured leg recall 0.963 / 0.966 / 0.932 / 0.981 (0.966 / 0.966 / 0.964 / 0.986 before the
// rule for legs on occupied space; its held-out cost in test_legs_classifier_real.cpp).
TEST(PeopleTrackingReal, PositiveBagsLegRecall) {
  FIELDLIDAR_REQUIRE_DATA("legs_2d/positive_1_extracted.bag");
  for (int b = 1; b <= 4; ++b) {
    LegPipeline2D pipeline(shipped());
    MatchCounts m;
    for (const auto& scan : test::positive_scans({b})) {
      const auto out = pipeline.process(scan.stamp_s, scan.points);
      std::vector<Eigen::Vector2d> legs;
      for (const auto& l : out.legs) legs.push_back(l.position_m);
      test::score_scan(legs, scan, 0.15, m, false);
    }
    std::printf("positive_%d: leg recall %.4f precision %.4f\n", b, m.recall(), m.precision());
    EXPECT_GE(m.recall(), 0.93) << b;
    EXPECT_GE(m.precision(), 0.93) << b;
  }
}

/// Every second beam of a scan: the same scenes seen by a laser of twice the angular step.
std::vector<Eigen::Vector2d> every_second(const std::vector<Eigen::Vector2d>& points) {
  std::vector<Eigen::Vector2d> out;
  for (std::size_t i = 0; i < points.size(); i += 2) out.push_back(points[i]);
  return out;
}

// A laser twice as coarse (0.70 deg): the classifier learned 0.35 deg scans (its scan_step_deg),
// and the pipeline resamples a scan 1.25 times as coarse or more to that step, its segments then
// scored with a margin of 0.5 (LegPipeline2DConfig::resample_min_ratio, resample_score_margin).
// Measured with the shipped classifier (trained on these bags), positive_1..4 leg recall: thinned
// 0.843 / 0.759 / 0.774 / 0.949 without, 0.938 / 0.957 / 0.929 / 0.995 with (0.969 / 0.983 /
// 0.961 / 0.998 unthinned); negative_2 false persons per scan (left, rear, right) 0 / 0.014 /
// 0.034 without, 0.007 / 0.048 / 0.083 with (0 / 0 / 0 unthinned). Held out: docs/people.md.
TEST(PeopleTrackingReal, CoarserLaserResampledToTheClassifiersStep) {
  FIELDLIDAR_REQUIRE_DATA("legs_2d/positive_1_extracted.bag");
  FIELDLIDAR_REQUIRE_DATA("legs_2d/negative_2.bag");
  auto plain = shipped();
  plain.resample_min_ratio = 0;
  for (int b = 1; b <= 4; ++b) {
    MatchCounts with, without;
    LegPipeline2D resampled(shipped()), raw(plain), native(shipped());
    std::size_t scans = 0, thin_resampled = 0, native_resampled = 0;
    for (const auto& scan : test::positive_scans({b})) {
      const auto thin = every_second(scan.points);
      ++scans;
      native_resampled += native.process(scan.stamp_s, scan.points).resampled;
      for (auto [pipeline, counts] : {std::pair{&resampled, &with}, std::pair{&raw, &without}}) {
        const auto out = pipeline->process(scan.stamp_s, thin);
        if (pipeline == &resampled) thin_resampled += out.resampled;
        std::vector<Eigen::Vector2d> legs;
        for (const auto& l : out.legs) legs.push_back(l.position_m);
        test::score_scan(legs, scan, 0.15, *counts, false);
      }
    }
    std::printf("positive_%d thinned: leg recall %.4f resampled, %.4f not\n", b, with.recall(),
                without.recall());
    EXPECT_EQ(thin_resampled, scans) << b;  // every thinned scan, no scan at its own step
    EXPECT_EQ(native_resampled, 0u) << b;
    EXPECT_GE(with.recall(), 0.92) << b;
    EXPECT_GE(with.recall(), without.recall() + 0.04) << b;
  }
  const double max_false_persons[] = {0.015, 0.06, 0.095};
  int i = 0;
  for (const char* topic : {"/left_scan", "/rear_scan", "/right_scan"}) {
    LegPipeline2D pipeline(shipped());
    const auto scans = test::load_leg_scans("legs_2d/negative_2.bag", topic, "");
    std::size_t persons = 0;
    for (const auto& s : scans)
      persons += pipeline.process(s.stamp_s, every_second(s.points)).people.size();
    const double per_scan = double(persons) / double(scans.size());
    std::printf("%s thinned: false persons/scan %.4f\n", topic, per_scan);
    EXPECT_LE(per_scan, max_false_persons[i++]) << topic;
  }
}

}  // namespace
}  // namespace fieldlidar::people
