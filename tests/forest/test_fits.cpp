// Circle and axis fits on partial arcs with noise and outliers.
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/forest/stem_slice.hpp"
#include "fieldlidar/forest/tracking.hpp"
#include "fieldlidar/forest/trunks.hpp"

namespace fieldlidar::forest {
namespace {

std::vector<Eigen::Vector2d> arc(Eigen::Vector2d c, double r, double from, double to, int n,
                                 double noise, std::mt19937& rng) {
  std::normal_distribution<double> g(0, noise);
  std::vector<Eigen::Vector2d> pts;
  for (int i = 0; i < n; ++i) {
    const double a = from + (to - from) * i / (n - 1);
    pts.push_back(c + (r + g(rng)) * Eigen::Vector2d(std::cos(a), std::sin(a)));
  }
  return pts;
}

TEST(ForestFits, CircleOnAQuarterArcWithNoise) {
  std::mt19937 rng(3);
  const auto pts = arc({5, 2}, 0.2, 2.4, 4.0, 15, 0.005, rng);
  const Circle c = fit_circle(pts, 0.03, 0.6);
  ASSERT_TRUE(c.ok);
  EXPECT_NEAR(c.radius_m, 0.2, 0.02);
  EXPECT_NEAR((c.center - Eigen::Vector2d(5, 2)).norm(), 0.0, 0.02);
  EXPECT_LT(c.residual_m, 0.008);
  EXPECT_NEAR(arc_coverage_deg(pts, c.center), (4.0 - 2.4) * 180 / std::numbers::pi, 3.0);
}

TEST(ForestFits, CircleRadiusStaysInItsBounds) {
  std::mt19937 rng(4);
  const auto line = arc({0, 0}, 50.0, 0.0, 0.004, 8, 0.0, rng);  // nearly straight
  const Circle c = fit_circle(line, 0.03, 0.6);
  ASSERT_TRUE(c.ok);
  EXPECT_GE(c.radius_m, 0.03);
  EXPECT_LE(c.radius_m, 0.6);
  EXPECT_FALSE(fit_circle(std::vector<Eigen::Vector2d>(2), 0.03, 0.6).ok);
}

TEST(ForestFits, AxisRejectsOutlyingCentres) {
  std::vector<Eigen::Vector3d> c;
  for (int i = 0; i < 10; ++i) c.emplace_back(1.0 + 0.1 * i * 0.2, 2.0, 0.2 * i);
  c[4].x() += 0.4;  // a branch
  const Axis a = fit_axis(c, 0.05);
  ASSERT_TRUE(a.ok);
  EXPECT_EQ(a.inliers.size(), 9u);
  EXPECT_NEAR(a.direction.x() / a.direction.z(), 0.1, 1e-6);
  EXPECT_NEAR(a.direction.y(), 0.0, 1e-9);
}

TEST(ForestFits, EmptyAndMismatchedInput) {
  PointCloud empty;
  EXPECT_TRUE(extract_trees(empty, {}).trees.empty());
  PointCloud one;
  one.push_back(Point{1, 1, 1});
  std::vector<std::uint8_t> flags(3, 0);
  EXPECT_THROW(extract_trees(one, flags), Error);
}

TEST(ForestFits, NanPointsAndNoGroundMakeNoTree) {
  PointCloud cloud;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (int i = 0; i < 500; ++i) cloud.push_back(Point{nan, nan, nan});
  for (int i = 0; i < 200; ++i)  // a flat patch, no ground flags: no stem in it
    cloud.push_back(Point{float(i % 20) * 0.1f, float(i / 20) * 0.1f, 0.0f});
  const auto r = extract_trees(cloud, std::vector<std::uint8_t>(cloud.size(), 0));
  EXPECT_TRUE(r.trees.empty());
  TrunkTracker tracker;
  EXPECT_FALSE(tracker.track(cloud, std::vector<std::uint8_t>(cloud.size(), 0)).tracked);
}

// One horizontal ring cast at circles (x, y, r) every 0.35 deg over +-8 deg (or from_deg to
// to_deg), a wall at 20 m behind: the returns a spinning sensor at the origin gets.
PointCloud cast_ring(const std::vector<Eigen::Vector3d>& circles, double from_deg = -8.0,
                     double to_deg = 8.0) {
  PointCloud cloud;
  cloud.fields.ring = true;
  for (double deg = from_deg; deg <= to_deg; deg += 0.35) {
    const Eigen::Vector2d u(std::cos(deg * std::numbers::pi / 180),
                            std::sin(deg * std::numbers::pi / 180));
    double best = 20.0;
    for (const auto& c : circles) {
      const double b = u.dot(c.head<2>()), d2 = c.head<2>().squaredNorm() - b * b;
      if (d2 <= c.z() * c.z()) best = std::min(best, b - std::sqrt(c.z() * c.z() - d2));
    }
    Point p{float(best * u.x()), float(best * u.y()), 0.0f};
    p.ring = 0;
    cloud.push_back(p);
  }
  return cloud;
}

TEST(ForestFits, StemBehindANarrowerOneIsOneSegment) {
  // A 0.6 m stem at 10 m behind a 0.16 m one at 6 m: its two sides make one segment.
  const auto cloud = cast_ring({{10.0, 0.0, 0.3}, {6.0, 0.0, 0.08}});
  const auto segs = segment_scan_lines(cloud, {});
  int wide = 0;
  for (const auto& s : segs)
    if (s.centroid.head<2>().norm() > 9.0 && s.centroid.head<2>().norm() < 10.5) {
      ++wide;
      EXPECT_GT(s.width_m, 0.5);
    }
  EXPECT_EQ(wide, 1);
  ScanSegmentConfig no_bridge;
  no_bridge.max_bridged_runs = 0;
  int parts = 0;
  for (const auto& s : segment_scan_lines(cloud, {}, no_bridge))
    parts += s.centroid.head<2>().norm() > 9.0 && s.centroid.head<2>().norm() < 10.5;
  EXPECT_EQ(parts, 2);
  // Two stems either side of the occluder at 10 and 10.8 m: not one circle, left apart.
  const auto two = cast_ring({{10.0, 0.25, 0.08}, {10.8, -0.27, 0.08}, {6.0, 0.0, 0.08}});
  int far = 0;
  for (const auto& s : segment_scan_lines(two, {}))
    far += s.centroid.head<2>().norm() > 9.0 && s.centroid.head<2>().norm() < 11.5;
  EXPECT_EQ(far, 2);
}

// Horizontal rings at heights z0, z0 + dz, ... cast like cast_ring; circles (x, y, r) stand on
// every ring, `extra(k)` adds circles on ring k only. Flat ground returns (flagged) around.
PointCloud cast_rings(int rings, double z0, double dz, const std::vector<Eigen::Vector3d>& circles,
                      const std::function<std::vector<Eigen::Vector3d>(int)>& extra,
                      std::vector<std::uint8_t>& is_ground, double from_deg = -8.0,
                      double to_deg = 8.0, double ground_x_sign = 1.0) {
  PointCloud cloud;
  cloud.fields.ring = true;
  is_ground.clear();
  for (int k = 0; k < rings; ++k) {
    auto all = circles;
    for (const auto& c : extra(k)) all.push_back(c);
    const PointCloud ring = cast_ring(all, from_deg, to_deg);
    for (auto p : ring.points) {
      p.z = float(z0 + dz * k);
      p.ring = std::uint16_t(k + 1);
      cloud.push_back(p);
      is_ground.push_back(0);
    }
  }
  for (double x = 4.0; x <= 12.0; x += 0.25)
    for (double y = -3.0; y <= 3.0; y += 0.25) {
      Point p{float(ground_x_sign * x), float(y), 0.0f};
      p.ring = 0;
      cloud.push_back(p);
      is_ground.push_back(1);
    }
  return cloud;
}

TEST(ForestFits, OneBranchWidenedLineBesideAnOccluderBoundsNothing) {
  // A 0.30 m stem at 8 m seen free on every line from 0.3 to 2.5 m, but on the line at 2.1 m a
  // branch stub at its left edge widens it and a thin stem at 5 m hides what lies beyond: that
  // one line's visible width (about 0.35 m) is no lower bound on the diameter.
  std::vector<std::uint8_t> ground;
  const auto cloud = cast_rings(
      12, 0.3, 0.2, {{8.0, 0.0, 0.15}},
      [](int k) {
        return k == 9 ? std::vector<Eigen::Vector3d>{{7.97, 0.19, 0.05}, {5.0, 0.17, 0.03}}
                      : std::vector<Eigen::Vector3d>{};
      },
      ground);
  const auto r = extract_trees(cloud, ground);
  ASSERT_EQ(r.trees.size(), 1u);
  EXPECT_FALSE(r.trees[0].dbh_uncertain);
  EXPECT_NEAR(r.trees[0].dbh_m, 0.30, 0.02);
}

TEST(ForestFits, LeaningStemsEdgesPinTheDiameterBelowAColumn) {
  // 0.32 m stems at 12 m leaning 0.06 m per metre across the line of sight, 17 lines from 0.3 to
  // 2.2 m, columns 0.35 deg apart (7.3 cm at 12 m, the stem 4.4 columns wide): each line's
  // width is quantised to whole columns, but the edges drift 1.5 columns over the lines and
  // their straight-line fit pins the width (measured within 0.5 cm). The mean of the per-line
  // widths read 0.293 to 0.326 m.
  double worst = 0;
  for (double y0 : {0.0, 0.018, 0.037, 0.055}) {
    std::vector<std::uint8_t> ground;
    const auto cloud = cast_rings(
        17, 0.3, 0.12, {},
        [&](int k) {
          return std::vector<Eigen::Vector3d>{{12.0, y0 + 0.06 * (0.3 + 0.12 * k), 0.16}};
        },
        ground);
    const auto r = extract_trees(cloud, ground);
    ASSERT_EQ(r.trees.size(), 1u);
    EXPECT_FALSE(r.trees[0].dbh_uncertain);
    worst = std::max(worst, std::abs(r.trees[0].dbh_m - 0.32));
  }
  EXPECT_LT(worst, 0.006);
}

TEST(ForestFits, EdgeReturnsTakenForGroundLeaveTheEdgeOpen) {
  // The same leaning stem with both edge returns of its two lowest lines flagged as ground (a
  // flared foot, a shrub against it): those lines look a column narrower on each side, but the
  // beams beside them returned at the stem's range, so they close no edge and the width holds.
  std::vector<std::uint8_t> ground;
  const auto stem = [](int k) {
    return std::vector<Eigen::Vector3d>{{12.0, 0.018 + 0.06 * (0.3 + 0.12 * k), 0.16}};
  };
  const auto cloud = cast_rings(17, 0.3, 0.12, {}, stem, ground);
  for (std::uint16_t ring : {1, 2}) {
    std::size_t lo = 0, hi = 0;
    double lo_az = 1e9, hi_az = -1e9;
    for (std::size_t i = 0; i < cloud.size(); ++i) {
      const auto& p = cloud.points[i];
      if (p.ring != ring || std::hypot(p.x, p.y) > 13.0) continue;
      const double az = std::atan2(p.y, p.x);
      if (az < lo_az) lo_az = az, lo = i;
      if (az > hi_az) hi_az = az, hi = i;
    }
    ground[lo] = ground[hi] = 1;
  }
  const auto r = extract_trees(cloud, ground);
  ASSERT_EQ(r.trees.size(), 1u);
  EXPECT_NEAR(r.trees[0].dbh_m, 0.32, 0.006);
}

TEST(ForestFits, StemCutNearBreastHeightIsMeasuredWhereItIsSeenWhole) {
  // A 0.32 m stem at 12 m leaning 0.06 m per metre, 24 lines from 0.3 to 3.5 m with 3 cm range
  // noise, behind a 2.4 m shrub at 7 m that hides its near-sensor side on every line within 1 m
  // of breast height: those lines see a sliver of two or three columns with one edge free. The
  // guess from the free edge's angle to the bearing of a circle fitted to the sliver (the circle
  // drawn into it) reads well under the diameter, flagged uncertain; the eight lines above the
  // shrub see both edges and measure it.
  std::vector<std::uint8_t> ground;
  auto cloud = cast_rings(
      24, 0.3, 0.14, {},
      [](int k) {
        const double z = 0.3 + 0.14 * k;
        std::vector<Eigen::Vector3d> c = {{12.0, 0.018 + 0.06 * z, 0.16}};
        if (z <= 2.4) c.emplace_back(7.0, -0.065, 0.12);
        return c;
      },
      ground);
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 0.03);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (ground[i]) continue;
    auto& p = cloud.points[i];
    const double range = std::hypot(p.x, p.y), k = (range + noise(rng)) / range;
    p.x = float(p.x * k);
    p.y = float(p.y * k);
  }
  const auto far_stem = [](const TreeResult& r) {
    std::vector<Tree> out;
    for (const auto& t : r.trees)
      if (t.at_height(1.3).head<2>().norm() > 10.0) out.push_back(t);
    return out;
  };
  const auto seen = far_stem(extract_trees(cloud, ground));
  ASSERT_EQ(seen.size(), 1u);
  EXPECT_FALSE(seen[0].dbh_uncertain);
  EXPECT_NEAR(seen[0].dbh_m, 0.32, 0.01);  // 0.321 (0.144, flagged, before)
  // Lines near breast height only (as before): a guess, flagged.
  TreeConfig near_only;
  near_only.silhouette_far_window_m = near_only.dbh_window_m;
  const auto guessed = far_stem(extract_trees(cloud, ground, near_only));
  ASSERT_EQ(guessed.size(), 1u);
  EXPECT_TRUE(guessed[0].dbh_uncertain);
  EXPECT_LT(guessed[0].dbh_m, 0.2);
}

TEST(ForestFits, StemBehindTheSensorAcrossMinusPiPi) {
  // A 0.40 m stem at 10 m straight behind the sensor: its returns' azimuths run from near +pi
  // to near -pi. It is one segment a line, its edges the outer ones (cut in two at -pi/pi
  // before: 24 half segments and no tree).
  std::vector<std::uint8_t> ground;
  const auto cloud = cast_rings(
      12, 0.3, 0.2, {{-10.0, 0.03, 0.2}}, [](int) { return std::vector<Eigen::Vector3d>{}; },
      ground, 172.0, 188.0, -1.0);
  const auto segs = segment_scan_lines(cloud, ground);
  int stem = 0;
  for (const auto& s : segs) stem += s.centroid.head<2>().norm() < 11.0;
  EXPECT_EQ(stem, 12);
  const auto r = extract_trees(cloud, ground);
  ASSERT_EQ(r.trees.size(), 1u);
  EXPECT_NEAR(r.trees[0].dbh_m, 0.40, 0.04);
  EXPECT_NEAR(r.trees[0].at_height(1.3).x(), -10.0, 0.05);
}

}  // namespace
}  // namespace fieldlidar::forest

namespace fieldlidar::forest {
namespace {

// Something stem-like that ends below breast height (a 0.6 m stump or a shrub's column, its top
// 1.15 m above the ground, 8 m ahead) under 16 lines from 0.05 to 1.55 m: its circle carried to
// breast height is a diameter where nothing stands. The lines above pass over it, so it is no
// trunk; a 0.3 m stem beside it, seen on every line, is kept, and so is a stem whose lines
// above 1.2 m are blocked by a nearer crown (nothing is known above it).
TEST(ForestFits, SomethingEndingBelowBreastHeightIsNoTrunkAStemHiddenAboveIs) {
  auto lines = [](bool crown) {
    std::vector<std::uint8_t> ground;
    auto cloud = cast_rings(
        16, 0.05, 0.1, {{8.0, -2.5, 0.15}},
        [crown](int k) {
          const double z = 0.05 + 0.1 * k;
          std::vector<Eigen::Vector3d> c;
          if (z < 1.2) c.emplace_back(8.0, 0.0, 0.3);
          // A second stem, 8 m ahead to the left: its lines from 1.25 m up meet a crown at 5 m.
          if (crown && z > 1.2)
            c.emplace_back(5.0, 1.55, 0.4);
          else
            c.emplace_back(8.0, 2.5, 0.15);
          return c;
        },
        ground, -25.0, 25.0);
    return std::pair(cloud, ground);
  };
  auto near = [](const TreeResult& r, double y) {
    int n = 0;
    for (const auto& t : r.trees) n += std::abs(t.at_height(1.3).y() - y) < 0.5;
    return n;
  };
  const auto [cloud, ground] = lines(false);
  TreeConfig no_rule;
  no_rule.min_top_seen_m = 0.0;
  const auto before = extract_trees(cloud, ground, no_rule);
  const auto after = extract_trees(cloud, ground);
  EXPECT_EQ(near(before, 0.0), 1);  // the shrub, taken for a trunk without the rule
  EXPECT_EQ(near(after, 0.0), 0);
  EXPECT_EQ(near(after, -2.5), 1);
  EXPECT_EQ(near(after, 2.5), 1);
  const auto [crowned, ground2] = lines(true);
  const auto hidden = extract_trees(crowned, ground2);
  EXPECT_EQ(near(extract_trees(crowned, ground2, no_rule), 2.5), 1);
  EXPECT_EQ(near(hidden, 0.0), 0);
  EXPECT_EQ(near(hidden, -2.5), 1);
  EXPECT_EQ(near(hidden, 2.5), 1);
}

}  // namespace
}  // namespace fieldlidar::forest

namespace fieldlidar::forest {
namespace {

// A stem slice with a branch: 400 returns on a 0.30 m circle (2 mm noise) and 250 along a
// branch leaving it, plus 50 scattered leaves. The RANSAC circle holds the stem (within 3 mm)
// where a least-squares circle through every point is pulled wide by the branch.
TEST(StemSlice, BranchDoesNotWidenTheStem) {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.002);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  PointCloud cloud;
  const Eigen::Vector2d c(4.0, -2.0);
  for (int i = 0; i < 400; ++i) {
    const double a = 2 * std::numbers::pi * u(rng), r = 0.15 + noise(rng);
    cloud.push_back(Point{float(c.x() + r * std::cos(a)), float(c.y() + r * std::sin(a)),
                          float(1.25 + 0.1 * u(rng))});
  }
  for (int i = 0; i < 250; ++i) {
    const double t = 0.15 + 0.6 * u(rng);
    cloud.push_back(Point{float(c.x() + t * 0.8 + noise(rng)), float(c.y() + t * 0.6 + noise(rng)),
                          float(1.25 + 0.1 * u(rng))});
  }
  for (int i = 0; i < 50; ++i)
    cloud.push_back(Point{float(c.x() - 0.5 + u(rng)), float(c.y() - 0.5 + u(rng)),
                          float(1.25 + 0.1 * u(rng))});
  ASSERT_TRUE(is_stem_slice(cloud));
  const StemSlice s = measure_stem_slice(cloud);
  ASSERT_TRUE(s.circle.ok);
  EXPECT_NEAR(2 * s.circle.radius_m, 0.30, 0.003);
  EXPECT_LT((s.circle.center - c).norm(), 0.003);
  EXPECT_GE(s.inliers, 380u);
  EXPECT_GT(s.arc_deg, 350.0);
  std::vector<Eigen::Vector2d> xy;
  for (const auto& p : cloud.points) xy.emplace_back(p.x, p.y);
  EXPECT_GT(2 * fit_circle(xy, 0.03, 1.5, 30).radius_m, 0.35);  // the branch read into it

  // A stem 2 m tall is no slice; a slice of scattered leaves holds no circle; bad settings.
  PointCloud tall = cloud;
  tall.push_back(Point{4.0f, -2.0f, 3.5f});
  EXPECT_FALSE(is_stem_slice(tall));
  PointCloud leaves;
  for (int i = 0; i < 40; ++i)
    leaves.push_back(Point{float(3 * u(rng)), float(3 * u(rng)), float(0.1 * u(rng))});
  EXPECT_FALSE(measure_stem_slice(leaves).circle.ok);
  EXPECT_FALSE(measure_stem_slice(PointCloud{}).circle.ok);
  StemSliceConfig bad;
  bad.inlier_band_m = 0.0;
  EXPECT_THROW(measure_stem_slice(cloud, bad), Error);
}

}  // namespace
}  // namespace fieldlidar::forest
