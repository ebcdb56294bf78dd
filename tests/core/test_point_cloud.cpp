#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "fieldlidar/core/point_cloud.hpp"

using namespace fieldlidar;

TEST(PointCloud, ValidityRejectsNanInfAndZero) {
  EXPECT_TRUE((Point{1.f, 0.f, 0.f}).is_valid());
  EXPECT_FALSE((Point{0.f, 0.f, 0.f}).is_valid());
  EXPECT_FALSE((Point{std::nanf(""), 1.f, 1.f}).is_valid());
  EXPECT_FALSE((Point{1.f, std::numeric_limits<float>::infinity(), 1.f}).is_valid());
}

TEST(PointCloud, BoundsAndRingsIgnoreInvalidPoints) {
  PointCloud c;
  c.push_back({1.f, -2.f, 3.f, 0.f, 0.f, 4});
  c.push_back({-1.f, 5.f, 0.5f, 0.f, 0.f, 7});
  c.push_back({0.f, 0.f, 0.f});
  c.push_back({std::nanf(""), 100.f, 100.f});
  EXPECT_EQ(c.size(), 4u);
  EXPECT_EQ(c.valid_count(), 2u);
  EXPECT_EQ(c.ring_count(), 8u);
  const auto b = compute_bounds(c);
  EXPECT_DOUBLE_EQ(b.min.x(), -1.0);
  EXPECT_DOUBLE_EQ(b.max.y(), 5.0);
  EXPECT_DOUBLE_EQ(b.max.z(), 3.0);
}

TEST(PointCloud, DropNearerThanKeepsFarPointsAndTheirLabels) {
  PointCloud c;
  c.fields.label = true;
  for (float x : {0.5f, 1.0f, 2.0f, 3.0f}) c.push_back({x, 0.f, 0.f}, 100u + std::uint32_t(x));
  c.push_back({NAN, 0.f, 0.f}, 7u);
  PointCloud same = c;
  drop_nearer_than(same, 0.0);  // off: untouched, invalid points too
  EXPECT_EQ(same.size(), 5u);
  drop_nearer_than(c, 2.0);  // 2 m itself is kept; NaN is dropped
  ASSERT_EQ(c.size(), 2u);
  ASSERT_TRUE(c.has_labels());
  EXPECT_FLOAT_EQ(c.points[0].x, 2.f);
  EXPECT_EQ(c.labels[1], 103u);
}

TEST(PointCloud, SelectKeepsLabelsAligned) {
  PointCloud c;
  c.fields.label = true;
  for (int i = 0; i < 5; ++i) c.push_back({float(i + 1), 0.f, 0.f}, 10u + i);
  const bool keep[] = {true, false, true, false, true};
  const auto s = select(c, keep);
  ASSERT_EQ(s.size(), 3u);
  ASSERT_TRUE(s.has_labels());
  EXPECT_EQ(s.labels[1], 12u);
  EXPECT_FLOAT_EQ(s.points[2].x, 5.f);
  const bool wrong[] = {true};
  EXPECT_THROW(select(c, wrong), std::invalid_argument);
}
