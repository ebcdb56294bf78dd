// The learned leg classifier: features, training on a separable synthetic set, YAML round trip.

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>
#include <string>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/people/leg_classifier.hpp"
#include "fieldlidar/people/leg_detector.hpp"

namespace fieldlidar::people {
namespace {

/// Points of an arc of a circle of radius r (m) centred at (cx, 0), facing the sensor at the
/// origin.
std::vector<Eigen::Vector2d> arc(double cx, double r, int n) {
  std::vector<Eigen::Vector2d> p;
  for (int j = 0; j < n; ++j) {
    const double a = M_PI + (double(j) / (n - 1) - 0.5) * 1.6;
    p.emplace_back(cx + r * std::cos(a), r * std::sin(a));
  }
  return p;
}

std::vector<Eigen::Vector2d> line(double x, double half_width, int n) {
  std::vector<Eigen::Vector2d> p;
  for (int j = 0; j < n; ++j) p.emplace_back(x, -half_width + 2 * half_width * j / (n - 1));
  return p;
}

/// Features of `pairs` leg-like arcs (label 1) and as many wall-like lines (label 0), drawn with
/// generator seed `seed`.
void arcs_and_lines(unsigned seed, int pairs, std::vector<SegmentFeatures>& x,
                    std::vector<char>& y) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> range(1.0, 6.0), radius(0.04, 0.08), width(0.2, 1.0);
  for (int i = 0; i < pairs; ++i) {
    const auto a = arc(range(rng), radius(rng), 6 + i % 8);
    x.push_back(segment_features(a, 0, a.size()));
    y.push_back(1);
    const auto l = line(range(rng), width(rng), 6 + i % 20);
    x.push_back(segment_features(l, 0, l.size()));
    y.push_back(0);
  }
}

TEST(LegClassifier, FeaturesOfAnArcAndALine) {
  const auto a = arc(2.0, 0.06, 9);
  const auto f = segment_features(a, 0, a.size());
  for (double v : f) EXPECT_TRUE(std::isfinite(v));
  EXPECT_EQ(f[0], 9.0);
  EXPECT_NEAR(f[4], 0.06, 1e-6);  // circle radius
  EXPECT_GT(f[11], 0.015);        // bulges toward the sensor: r (1 - cos 0.8) = 0.018 m
  EXPECT_NEAR(f[9], 1.95, 0.02);  // range of the centroid
  const auto l = line(3.0, 0.5, 20);
  const auto g = segment_features(l, 0, l.size());
  for (double v : g) EXPECT_TRUE(std::isfinite(v));
  EXPECT_NEAR(g[3], 1.0, 1e-9);  // bend of a straight segment
  EXPECT_NEAR(g[6], 0.0, 1e-9);  // no spread across its line
  EXPECT_EQ(segment_feature_names().size(), kSegmentFeatures);
}

TEST(LegClassifier, LearnsArcsFromWallsAndRoundTripsThroughYaml) {
  std::vector<SegmentFeatures> x;
  std::vector<char> y;
  arcs_and_lines(3, 400, x, y);
  BoostOptions o;
  o.rounds = 20;
  const auto model = train_leg_classifier(x, y, o);
  EXPECT_EQ(model.trees.size(), 20u);
  std::size_t right = 0;
  for (std::size_t i = 0; i < x.size(); ++i) right += model.is_leg(x[i]) == bool(y[i]);
  EXPECT_GE(double(right) / double(x.size()), 0.98);
  const auto back = leg_classifier_from_yaml(to_yaml(model), "model.yaml");
  ASSERT_EQ(back.trees.size(), model.trees.size());
  EXPECT_DOUBLE_EQ(back.threshold, model.threshold);
  for (std::size_t i = 0; i < x.size(); i += 37)
    EXPECT_NEAR(back.score(x[i]), model.score(x[i]), 1e-6);
  // A trained classifier carries no occupied-space margins; set ones travel with it.
  EXPECT_TRUE(std::isinf(back.occupied_score_min) && back.occupied_score_min < 0);
  EXPECT_EQ(to_yaml(model).find("occupied_leg"), std::string::npos);
  auto with_margins = model;
  with_margins.occupied_score_min = 3.0;
  with_margins.occupied_evidence_min = 7.0;
  const auto back2 = leg_classifier_from_yaml(to_yaml(with_margins), "model.yaml");
  EXPECT_DOUBLE_EQ(back2.occupied_score_min, 3.0);
  EXPECT_DOUBLE_EQ(back2.occupied_evidence_min, 7.0);
  // So does the training scans' angular step (unknown, 0, unless set).
  EXPECT_EQ(back.scan_step_rad, 0.0);
  auto with_step = model;
  with_step.scan_step_rad = 0.3515625 * M_PI / 180.0;
  EXPECT_NEAR(leg_classifier_from_yaml(to_yaml(with_step), "model.yaml").scan_step_rad,
              with_step.scan_step_rad, 1e-9);
  std::string bad_step = to_yaml(with_step);
  bad_step.replace(bad_step.find("scan_step_deg: "), 15, "scan_step_deg: -");
  EXPECT_THROW(leg_classifier_from_yaml(bad_step, "model.yaml"), Error);
  // The classifier drives detect_legs_2d when set.
  LegDetectorConfig c = default_2d_legs();
  c.use_background = false;
  c.classifier = std::make_shared<const LegClassifier>(model);
  auto scan = arc(2.0, 0.06, 9);
  const auto wall = line(4.0, 0.8, 40);
  scan.insert(scan.end(), wall.begin(), wall.end());
  const auto d = detect_legs_2d(scan, c);
  ASSERT_EQ(d.legs.size(), 1u);
  EXPECT_NEAR(d.legs[0].position_m.x(), 1.95, 0.03);
}

// Features excluded from training are never split on, and an unknown name is an error.
TEST(LegClassifier, ExcludedFeaturesAreNeverUsed) {
  std::vector<SegmentFeatures> x;
  std::vector<char> y;
  arcs_and_lines(5, 200, x, y);
  BoostOptions o;
  o.rounds = 30;
  const auto names = segment_feature_names();
  const auto all = train_leg_classifier(x, y, o);
  std::set<int> used;
  for (const auto& t : all.trees) used.insert(t.feature);
  ASSERT_FALSE(used.empty());
  for (const int f : used) o.excluded_features.push_back(names[std::size_t(f)]);
  const auto without = train_leg_classifier(x, y, o);
  ASSERT_FALSE(without.trees.empty());
  for (const auto& t : without.trees)
    EXPECT_EQ(used.count(t.feature), 0u) << names[std::size_t(t.feature)];
  o.excluded_features = {"range_meters"};
  EXPECT_THROW(train_leg_classifier(x, y, o), Error);
}

TEST(LegClassifier, RejectsBadInput) {
  std::vector<SegmentFeatures> x(3);
  std::vector<char> y(3, 0);
  EXPECT_THROW(train_leg_classifier(x, y), std::invalid_argument);
  EXPECT_THROW(train_leg_classifier(x, std::vector<char>(2, 1)), std::invalid_argument);
  EXPECT_THROW(leg_classifier_from_yaml("foo: 1\n", "m.yaml"), Error);
  EXPECT_THROW(leg_classifier_from_yaml("leg_classifier:\n  trees: []\n", "m.yaml"), Error);
  EXPECT_THROW(
      leg_classifier_from_yaml("leg_classifier:\n  trees:\n    - {feature: nope, threshold: "
                               "1, below: {feature: points, threshold: 1, below: 0, "
                               "above: 0}, above: {feature: points, threshold: 1, "
                               "below: 0, above: 0}}\n",
                               "m.yaml"),
      Error);
  EXPECT_THROW(leg_classifier_from_yaml("leg_classifier: [\n", "m.yaml"), Error);
}

}  // namespace
}  // namespace fieldlidar::people
