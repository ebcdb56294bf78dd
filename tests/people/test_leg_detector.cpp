#include <gtest/gtest.h>

#include <cmath>

#include "fieldlidar/people/leg_detector.hpp"
#include "synthetic_scan.hpp"

namespace fieldlidar::people {
namespace {

using test::Circle;
using test::Wall;

std::vector<Eigen::Vector2d> arc_points(Eigen::Vector2d c, double r, double a0, double a1, int n) {
  std::vector<Eigen::Vector2d> pts;
  for (int i = 0; i < n; ++i) {
    const double a = a0 + (a1 - a0) * i / (n - 1);
    pts.push_back(c + r * Eigen::Vector2d(std::cos(a), std::sin(a)));
  }
  return pts;
}

TEST(ArcFeatures, SemicircleHasExactPathChordAndCurve) {
  const double r = 0.06;
  const int n = 11;
  const auto pts = arc_points({2, 1}, r, M_PI / 2, 3 * M_PI / 2, n);
  const auto f = compute_arc_features(pts);
  const double path = (n - 1) * 2 * r * std::sin(M_PI / (2 * (n - 1)));
  EXPECT_EQ(f.points, std::size_t(n));
  EXPECT_NEAR(f.path_m, path, 1e-12);
  EXPECT_NEAR(f.chord_m, 2 * r, 1e-12);
  EXPECT_NEAR(f.curve, path / (2 * r), 1e-12);
  EXPECT_NEAR(f.circle_radius_m, r, 1e-9);
  EXPECT_NEAR((f.circle_center_m - Eigen::Vector2d(2, 1)).norm(), 0, 1e-9);
  EXPECT_LT(f.circle_rms_m, 1e-9);
}

TEST(ArcFeatures, StraightLineHasCurveOne) {
  std::vector<Eigen::Vector2d> pts;
  for (int i = 0; i < 6; ++i) pts.emplace_back(1.0, 0.05 * i);
  const auto f = compute_arc_features(pts);
  EXPECT_NEAR(f.path_m, 0.25, 1e-12);
  EXPECT_NEAR(f.chord_m, 0.25, 1e-12);
  EXPECT_NEAR(f.curve, 1.0, 1e-12);
  EXPECT_TRUE(!std::isfinite(f.circle_radius_m) || f.circle_radius_m > 100);
  EXPECT_NEAR(f.midpoint_m.y(), 0.125, 1e-12);
}

TEST(ArcFeatures, SinglePointHasInfiniteCurve) {
  const std::vector<Eigen::Vector2d> pts{{1, 1}};
  const auto f = compute_arc_features(pts);
  EXPECT_EQ(f.path_m, 0);
  EXPECT_FALSE(std::isfinite(f.curve));
  EXPECT_EQ(classify_arc(f, LegDetectorConfig{}), ArcVerdict::kCurve);
}

TEST(SplitByJump, SplitsAtGapsOnly) {
  const std::vector<Eigen::Vector2d> pts{{0, 0}, {0, 0.1}, {0, 0.2}, {0, 0.5}, {0, 0.6}, {0, 2}};
  const auto s = split_by_jump(pts, 0.13);
  ASSERT_EQ(s.size(), 3u);
  EXPECT_EQ(s[0], std::make_pair(std::size_t(0), std::size_t(3)));
  EXPECT_EQ(s[1], std::make_pair(std::size_t(3), std::size_t(5)));
  EXPECT_EQ(s[2], std::make_pair(std::size_t(5), std::size_t(6)));
  EXPECT_TRUE(split_by_jump(std::vector<Eigen::Vector2d>{}, 0.1).empty());
}

TEST(ClassifyArc, SeedBoundsAreStrict) {
  LegDetectorConfig c;
  ArcFeatures f;
  f.points = 5;
  f.path_m = 0.2;
  f.chord_m = 0.12;
  f.curve = f.path_m / f.chord_m;
  f.circle_radius_m = 0.06;
  f.circle_rms_m = 0.001;
  EXPECT_EQ(classify_arc(f, c), ArcVerdict::kLeg);
  f.curve = c.curve_max;  // Curve < delta_c is strict
  EXPECT_EQ(classify_arc(f, c), ArcVerdict::kCurve);
  f.curve = 1.5;
  f.path_m = c.path_max_m;  // L_k < L_max is strict
  EXPECT_EQ(classify_arc(f, c), ArcVerdict::kPathLength);
  f.path_m = c.path_min_m;
  EXPECT_EQ(classify_arc(f, c), ArcVerdict::kPathLength);
  f.path_m = 0.2;
  f.points = 2;
  EXPECT_EQ(classify_arc(f, c), ArcVerdict::kLeg);  // addition off
  c.use_min_points = true;
  EXPECT_EQ(classify_arc(f, c), ArcVerdict::kTooFewPoints);
  f.points = 5;
  c.use_circle_fit = true;
  f.circle_radius_m = 0.5;
  EXPECT_EQ(classify_arc(f, c), ArcVerdict::kCircle);
  f.circle_radius_m = 0.06;
  c.use_curve_min = true;
  f.curve = 1.01;
  EXPECT_EQ(classify_arc(f, c), ArcVerdict::kStraight);
}

TEST(DetectLegs2d, PersonInFrontOfWallIsFoundAtTheLegsMidpoint) {
  // Two legs of radius 6 cm, centres 0.25 m apart, 3 m ahead; a wall 6 m ahead; a thick post.
  const Circle left{{3.0, 0.125}, 0.06}, right{{3.0, -0.125}, 0.06};
  const auto scan =
      test::cast_scan({left, right, Circle{{4.0, 2.0}, 0.3}}, {Wall{{6, -5}, {6, 5}}});
  LegDetectorConfig c;
  // The seed's bounds alone also accept the straight sliver of wall seen between the legs'
  // shadows (Curve = 1 < delta_c, L_k inside the bounds); it is 3 m behind, so it pairs with none.
  const auto seed_only = detect_legs_2d(scan, c);
  ASSERT_EQ(seed_only.legs.size(), 3u);
  EXPECT_NEAR(seed_only.legs[1].position_m.x(), 6.0, 1e-6);
  ASSERT_EQ(seed_only.people.size(), 1u);
  c.use_curve_min = true;  // the addition that rejects straight arcs
  const auto d = detect_legs_2d(scan, c);
  ASSERT_EQ(d.legs.size(), 2u);
  ASSERT_EQ(d.people.size(), 1u);
  // The arc midpoint lies on the visible front of each leg: between the centre and r toward the
  // sensor.
  const Eigen::Vector2d p = d.people[0].position_m;
  EXPECT_NEAR(p.y(), 0.0, 0.01);
  EXPECT_GT(p.x(), 3.0 - 0.06);
  EXPECT_LT(p.x(), 3.0);
  // Legs farther apart than dist_max are not a person.
  const auto far = test::cast_scan({Circle{{3.0, 0.5}, 0.06}, Circle{{3.0, -0.5}, 0.06}}, {});
  const auto d2 = detect_legs_2d(far, c);
  EXPECT_EQ(d2.legs.size(), 2u);
  EXPECT_EQ(d2.people.size(), 0u);
}

TEST(DetectLegs2d, RangeBoundsDropFarAndNearPoints) {
  const auto scan = test::cast_scan({Circle{{3.0, 0.125}, 0.06}, Circle{{3.0, -0.125}, 0.06}}, {});
  LegDetectorConfig c;
  c.range_max_m = 2.5;
  EXPECT_TRUE(detect_legs_2d(scan, c).legs.empty());
  c.range_max_m = 15;
  c.range_min_m = 3.5;
  EXPECT_TRUE(detect_legs_2d(scan, c).legs.empty());
}

TEST(PairLegs, ClosestPairsFirstEachLegOnce) {
  LegDetection d;
  d.legs = {{{0, 0}, 1, 0}, {{0, 0.2}, 1, 1}, {{0, 0.5}, 1, 2}, {{0, 0.75}, 1, 3}};
  LegDetectorConfig c;
  c.pair_distance_max_m = 0.4;
  pair_legs(d, c);
  ASSERT_EQ(d.people.size(), 2u);
  EXPECT_NEAR(d.people[0].position_m.y(), 0.1, 1e-12);
  EXPECT_NEAR(d.people[1].position_m.y(), 0.625, 1e-12);
}

TEST(DetectLegs3d, RingsOfAClusterAreMergedIntoLegs) {
  // Two vertical cylinders (legs) sampled on 4 rings at 0.2 deg, plus a wide box cluster.
  PointCloud cloud;
  std::vector<std::uint32_t> person, box;
  for (std::uint16_t ring = 0; ring < 4; ++ring) {
    for (const auto& c : {Circle{{4.0, 0.13}, 0.06}, Circle{{4.0, -0.13}, 0.06}}) {
      for (double a = -0.2; a <= 0.2; a += 0.2 * M_PI / 180) {
        const Eigen::Vector2d dir(std::cos(a), std::sin(a));
        if (auto t = test::hit_circle(dir, c)) {
          Point p;
          p.x = float(dir.x() * *t);
          p.y = float(dir.y() * *t);
          p.z = float(-0.3 + 0.1 * ring);
          p.ring = ring;
          person.push_back(std::uint32_t(cloud.size()));
          cloud.push_back(p);
        }
      }
    }
    for (double y = 1.0; y <= 2.0; y += 0.02) {
      Point p;
      p.x = 5;
      p.y = float(y);
      p.z = float(-0.3 + 0.1 * ring);
      p.ring = ring;
      box.push_back(std::uint32_t(cloud.size()));
      cloud.push_back(p);
    }
  }
  const std::vector<std::vector<std::uint32_t>> clusters{person, box};
  LegDetectorConfig c;
  const auto d = detect_legs_3d(cloud, clusters, c);
  ASSERT_EQ(d.legs.size(), 2u);
  EXPECT_EQ(d.legs[0].rings, 4);
  ASSERT_EQ(d.people.size(), 1u);
  EXPECT_NEAR(d.people[0].position_m.y(), 0.0, 0.01);
  EXPECT_NEAR(d.people[0].position_m.x(), 3.97, 0.03);
  c.min_rings = 5;  // more rings than the cloud has
  EXPECT_TRUE(detect_legs_3d(cloud, clusters, c).legs.empty());
}

}  // namespace
}  // namespace fieldlidar::people
