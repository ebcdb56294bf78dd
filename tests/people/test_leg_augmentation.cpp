// Training-set augmentation of the leg classifier: a segment re-seen farther and narrower by rays
// of the scan's angular step.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "fieldlidar/people/leg_augmentation.hpp"
#include "fieldlidar/people/leg_classifier.hpp"
#include "fieldlidar/people/leg_detector.hpp"

namespace fieldlidar::people {
namespace {

constexpr double kStep = 0.3516 * M_PI / 180.0;

/// A scan by rays kStep apart over -20..20 deg: a leg (circle of radius 0.06 m centred 2 m ahead)
/// in front of a wall at x = 5 m.
std::vector<Eigen::Vector2d> leg_before_wall() {
  std::vector<Eigen::Vector2d> pts;
  const Eigen::Vector2d c(2.0, 0.0);
  for (double b = -20 * M_PI / 180; b <= 20 * M_PI / 180; b += kStep) {
    const Eigen::Vector2d u(std::cos(b), std::sin(b));
    double range = 5.0 / u.x();
    const double along = u.dot(c), d2 = (c - along * u).squaredNorm(), r2 = 0.06 * 0.06;
    if (d2 < r2) range = along - std::sqrt(r2 - d2);
    pts.push_back(range * u);
  }
  return pts;
}

std::pair<std::size_t, std::size_t> leg_segment(const std::vector<Eigen::Vector2d>& pts) {
  for (const auto& [b, e] : split_by_jump(pts, 0.13))
    if (pts[b].norm() < 3.0) return {b, e};
  return {0, 0};
}

double chord(const AugmentedSegment& s) {
  return (s.points[s.end - 1] - s.points[s.begin]).norm();
}

TEST(LegAugmentation, ReseenFartherHasFewerReturnsAndKeepsItsNeighbours) {
  const auto pts = leg_before_wall();
  EXPECT_NEAR(median_angular_step_rad(pts), kStep, 1e-6);
  const auto [b, e] = leg_segment(pts);
  ASSERT_GT(e - b, 8u);
  std::mt19937_64 rng(3);
  const auto same = reseen_segment(pts, b, e, 1.0, 1.0, kStep, 0.0, 0.0, rng);
  EXPECT_NEAR(double(same.end - same.begin), double(e - b), 1.0);
  const auto far = reseen_segment(pts, b, e, 2.0, 1.0, kStep, 0.5, 0.0, rng);
  ASSERT_EQ(far.points.size(), far.end - far.begin + 2);  // both neighbours kept
  EXPECT_NEAR(double(far.end - far.begin), 0.5 * double(e - b), 1.0);
  Eigen::Vector2d m = Eigen::Vector2d::Zero();
  for (std::size_t j = far.begin; j < far.end; ++j) m += far.points[j];
  EXPECT_NEAR((m / double(far.end - far.begin)).norm(), 2 * 1.95, 0.06);
  // The wall keeps its range offset to the leg's nearest return, one step beside the segment.
  const double offset_before = pts[b - 1].norm() - pts[(b + e) / 2].norm();
  double nearest = 1e9;
  for (std::size_t j = far.begin; j < far.end; ++j)
    nearest = std::min(nearest, far.points[j].norm());
  EXPECT_NEAR(far.points.front().norm() - nearest, offset_before, 0.02);
  EXPECT_EQ(split_by_jump(far.points, 0.13).size(), 3u);
  // Narrower: the chord shrinks with the width factor.
  const auto narrow = reseen_segment(pts, b, e, 1.0, 0.7, kStep, 0.0, 0.0, rng);
  EXPECT_NEAR(chord(narrow), 0.7 * chord(same), 0.015);
  EXPECT_LT(narrow.end - narrow.begin, same.end - same.begin);
  // Far beyond one step per leg width: one return is kept.
  const auto tiny = reseen_segment(pts, b, e, 40.0, 0.7, kStep, 0.9, 0.0, rng);
  EXPECT_GE(tiny.end - tiny.begin, 1u);
}

TEST(LegAugmentation, CopiesCarryTheLabelOfTheirSegment) {
  const auto pts = leg_before_wall();
  const auto [b, e] = leg_segment(pts);
  Eigen::Vector2d leg = Eigen::Vector2d::Zero();
  for (std::size_t j = b; j < e; ++j) leg += pts[j];
  leg /= double(e - b);
  const std::vector<Eigen::Vector2d> truth = {leg};
  SegmentSamples plain, augmented;
  collect_segment_samples(pts, truth, 0.3, 15.0, 0.13, 0.15, 0.5, plain);
  SegmentAugmentationConfig a;
  a.copies = 3;
  collect_segment_samples(pts, truth, 0.3, 15.0, 0.13, 0.15, 0.5, augmented, true, a);
  EXPECT_EQ(augmented.features.size(), 4 * plain.features.size());
  EXPECT_EQ(std::count(augmented.is_leg.begin(), augmented.is_leg.end(), char(1)), 4);
  // The same inputs give the same copies.
  SegmentSamples again;
  collect_segment_samples(pts, truth, 0.3, 15.0, 0.13, 0.15, 0.5, again, true, a);
  EXPECT_EQ(again.features, augmented.features);
  // Copies landing beyond range_max_m are dropped.
  a.range_factor_min = a.range_factor_max = 4.0;
  a.range_max_m = 6.0;
  SegmentSamples capped;
  collect_segment_samples(pts, truth, 0.3, 15.0, 0.13, 0.15, 0.5, capped, true, a);
  EXPECT_EQ(std::count(capped.is_leg.begin(), capped.is_leg.end(), char(1)), 1);
}

}  // namespace
}  // namespace fieldlidar::people
