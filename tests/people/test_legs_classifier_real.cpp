// The learned leg classifier on the real annotated 2D scans of ../shared/data/legs_2d, evaluated
// on held-out data only: leave one positive bag out for recall and precision (trained on the
// other three positive bags and all of negative_2.bag), leave one of negative_2.bag's three scan
// topics out for false persons per scan (trained on all positive bags and the other two topics).

#include <gtest/gtest.h>

#include <cstdio>
#include <memory>

#include "legs_data.hpp"

namespace fieldlidar::people {
namespace {

struct Data {
  std::vector<std::vector<test::LegScan>> pos;  // positive_1..4
  std::vector<std::vector<test::LegScan>> neg;  // negative_2 left, rear, right
  std::vector<SegmentSamples> pos_samples, neg_samples;
};

SegmentSamples samples_of(const std::vector<test::LegScan>& scans, const LegDetectorConfig& c) {
  SegmentSamples s;
  for (const auto& scan : scans)
    collect_segment_samples(scan.points, scan.legs, c.range_min_m, c.range_max_m, c.segment_jump_m,
                            0.15, 0.5, s);
  return s;
}

const Data& data() {
  static const Data d = [] {
    Data d;
    const auto base = default_2d_legs();
    for (int b = 1; b <= 4; ++b) {
      d.pos.push_back(test::positive_scans({b}));
      d.pos_samples.push_back(samples_of(d.pos.back(), base));
    }
    for (const char* t : {"/left_scan", "/rear_scan", "/right_scan"}) {
      d.neg.push_back(test::load_leg_scans("legs_2d/negative_2.bag", t, ""));
      d.neg_samples.push_back(samples_of(d.neg.back(), base));
    }
    return d;
  }();
  return d;
}

/// Trains on every positive bag but `skip_pos` and every negative topic but `skip_neg` (-1 = none).
std::shared_ptr<const LegClassifier> train_without(int skip_pos, int skip_neg,
                                                   const BoostOptions& o) {
  const auto& d = data();
  SegmentSamples s;
  for (int b = 0; b < int(d.pos_samples.size()); ++b)
    if (b != skip_pos) s.append(d.pos_samples[std::size_t(b)]);
  for (int t = 0; t < int(d.neg_samples.size()); ++t)
    if (t != skip_neg) s.append(d.neg_samples[std::size_t(t)]);
  return std::make_shared<const LegClassifier>(train_leg_classifier(s.features, s.is_leg, o));
}

struct HeldOut {
  MatchCounts legs;
  std::size_t false_persons = 0, negative_scans = 0;
  double recall() const { return legs.recall(); }
  double precision() const { return legs.precision(); }
  double false_persons_per_scan() const {
    return negative_scans ? double(false_persons) / double(negative_scans) : 0.0;
  }
};

HeldOut held_out(const BoostOptions& o, bool background) {
  const auto& d = data();
  HeldOut h;
  auto config = default_2d_legs();
  config.use_background = background;
  for (int b = 0; b < int(d.pos.size()); ++b) {
    config.classifier = train_without(b, -1, o);
    const auto s = test::score_legs(config, d.pos[std::size_t(b)], {});
    std::printf("  held-out positive_%d: recall %.4f precision %.4f\n", b + 1, s.recall,
                s.precision);
    h.legs += s.legs;
  }
  for (int t = 0; t < int(d.neg.size()); ++t) {
    config.classifier = train_without(-1, t, o);
    const auto s = test::score_legs(config, {}, d.neg[std::size_t(t)]);
    std::printf("  held-out negative topic %d: false persons/scan %.4f\n", t,
                s.false_persons_per_scan);
    h.false_persons +=
        std::size_t(std::lround(s.false_persons_per_scan * double(d.neg[std::size_t(t)].size())));
    h.negative_scans += d.neg[std::size_t(t)].size();
  }
  return h;
}

// Measured held out (Release): recall 0.8299, precision 0.6244, 0.4693 false persons per scan;
// the shipped bounds detector (in-sample bounds) gives 0.820 / 0.442 / 0.915. The targets
// (0.90 / 0.90 / 0.02) are not met: on held-out bags the classifier's errors are bag-specific
// (positive_3: recall ~0.6 at every setting). These bounds catch regressions.
TEST(LegsClassifierReal, HeldOutFigures) {
  FIELDLIDAR_REQUIRE_DATA("legs_2d/positive_1_extracted.bag");
  FIELDLIDAR_REQUIRE_DATA("legs_2d/negative_2.bag");
  const auto h = held_out(BoostOptions{}, true);
  std::printf(
      "held out, classifier + background: recall %.4f precision %.4f false persons/scan "
      "%.4f\n",
      h.recall(), h.precision(), h.false_persons_per_scan());
  EXPECT_GE(h.recall(), 0.82);
  EXPECT_GE(h.precision(), 0.615);
  EXPECT_LE(h.false_persons_per_scan(), 0.48);
  EXPECT_EQ(h.negative_scans, 1304u);
  // Better than the shipped bounds on all three figures.
  const auto& d = data();
  std::vector<test::LegScan> pos, neg;
  for (const auto& b : d.pos) pos.insert(pos.end(), b.begin(), b.end());
  for (const auto& t : d.neg) neg.insert(neg.end(), t.begin(), t.end());
  const auto bounds = test::score_legs(default_2d_legs(), pos, neg);
  std::printf("shipped bounds: recall %.4f precision %.4f false persons/scan %.4f\n", bounds.recall,
              bounds.precision, bounds.false_persons_per_scan);
  EXPECT_GE(h.recall(), bounds.recall);
  EXPECT_GT(h.precision(), bounds.precision + 0.1);
  EXPECT_LT(h.false_persons_per_scan(), 0.6 * bounds.false_persons_per_scan);
}

// Other settings, held out too, for the record (no regression bound: they are alternatives).
TEST(LegsClassifierReal, HeldOutAlternatives) {
  FIELDLIDAR_REQUIRE_DATA("legs_2d/positive_1_extracted.bag");
  FIELDLIDAR_REQUIRE_DATA("legs_2d/negative_2.bag");
  for (int depth : {1, 2})
    for (double th : {0.0, -0.75})
      for (bool bg : {false, true}) {
        BoostOptions o;
        o.depth = depth;
        o.threshold = th;
        const auto h = held_out(o, bg);
        std::printf(
            "depth %d threshold %.2f background %d: recall %.4f precision %.4f false "
            "persons/scan %.4f\n",
            depth, th, int(bg), h.recall(), h.precision(), h.false_persons_per_scan());
        EXPECT_GT(h.recall(), 0.3);
      }
}

}  // namespace
}  // namespace fieldlidar::people
