// Circle and axis fits on partial arcs with noise and outliers.
#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include "fieldlidar/core/error.hpp"
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

}  // namespace
}  // namespace fieldlidar::forest
