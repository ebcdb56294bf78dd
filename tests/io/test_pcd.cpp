#include <cmath>
#include <fstream>
#include <limits>

#include <gtest/gtest.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/pcd.hpp"
#include "test_data.hpp"

using namespace fieldlidar;

namespace {
/// An organized 8 x 6 scan with every field filled and one no-return cell.
PointCloud organized_scan() {
  PointCloud c;
  c.fields = {.intensity = true, .ring = true, .time = true, .label = true};
  for (std::uint16_t r = 0; r < 6; ++r)
    for (int col = 0; col < 8; ++col) {
      Point p{1.5f * col - 3.1f, 0.25f * r + 0.123456f, -1.7f + 0.01f * col, float(r * 8 + col)};
      p.ring = r;
      p.time = 1e-3f * col + 1e-5f * r;
      c.points.push_back(p);
      c.labels.push_back(100u * r + col);
    }
  c.points[5] = Point{};  // a no-return
  c.points[5].ring = 0;
  c.width = 8;
  c.height = 6;
  return c;
}

void expect_equal(const PointCloud& a, const PointCloud& b) {
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(a.width, b.width);
  EXPECT_EQ(a.height, b.height);
  EXPECT_EQ(a.fields, b.fields);
  EXPECT_EQ(a.labels, b.labels);
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a.points[i].x, b.points[i].x) << i;
    EXPECT_EQ(a.points[i].y, b.points[i].y) << i;
    EXPECT_EQ(a.points[i].z, b.points[i].z) << i;
    EXPECT_EQ(a.points[i].intensity, b.points[i].intensity) << i;
    EXPECT_EQ(a.points[i].ring, b.points[i].ring) << i;
    EXPECT_EQ(a.points[i].time, b.points[i].time) << i;
  }
}
}  // namespace

TEST(Pcd, RoundTripAsciiBinaryCompressed) {
  const auto c = organized_scan();
  const auto dir = test::temp_dir("pcd_rt");
  io::write_pcd(dir / "a.pcd", c, {.binary = false});
  io::write_pcd(dir / "b.pcd", c, {.binary = true});
  io::write_pcd(dir / "c.pcd", c, {.binary = true, .compressed = true});
  for (const char* f : {"a.pcd", "b.pcd", "c.pcd"}) {
    SCOPED_TRACE(f);
    expect_equal(io::read_pcd(dir / f), c);
  }
  std::ifstream in(dir / "c.pcd");
  std::string text((std::istreambuf_iterator<char>(in)), {});
  EXPECT_NE(text.find("DATA binary_compressed"), std::string::npos);
  EXPECT_THROW(io::write_pcd(dir / "a.pcd", c), Error);
  EXPECT_NO_THROW(io::write_pcd(dir / "a.pcd", c, {.overwrite = true}));
}

TEST(Pcd, AbsoluteTimestampBecomesStampAndOffsets) {
  PointCloud c;
  c.fields.time = true;
  for (int i = 0; i < 20; ++i) {
    Point p{1.f + i, 2.f, 3.f};
    p.time = 0.005f * i;
    c.push_back(p);
  }
  c.stamp_s = 1631322303.25;
  const auto dir = test::temp_dir("pcd_stamp");
  io::write_pcd(dir / "s.pcd", c);
  const auto back = io::read_pcd(dir / "s.pcd");
  EXPECT_NEAR(back.stamp_s, c.stamp_s, 1e-6);
  for (int i = 0; i < 20; ++i) EXPECT_NEAR(back.points[i].time, 0.005 * i, 1e-6);
}

TEST(Pcd, HandWrittenAsciiWithOusterStyleFields) {
  // Ouster driver layout: t is uint32 ns from the sweep start, ring uint16, intensity float.
  const auto dir = test::temp_dir("pcd_ouster");
  std::ofstream(dir / "o.pcd") << "# comment\nVERSION .7\nFIELDS x y z intensity t ring\n"
                                  "SIZE 4 4 4 4 4 2\nTYPE F F F F U U\nCOUNT 1 1 1 1 1 1\n"
                                  "WIDTH 3\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\n"
                                  "DATA ascii\n1 2 3 10 0 0\n4 5 6 20 50000000 7\n"
                                  "-1 -2 -3 30 99000000 63\n";
  const auto c = io::read_pcd(dir / "o.pcd");
  ASSERT_EQ(c.size(), 3u);
  EXPECT_TRUE(c.fields.ring && c.fields.time && c.fields.intensity);
  EXPECT_EQ(c.points[2].ring, 63);
  EXPECT_NEAR(c.points[1].time, 0.05, 1e-7);
  EXPECT_NEAR(c.points[2].time, 0.099, 1e-7);
  EXPECT_EQ(c.stamp_s, 0.0);
}

TEST(Pcd, NanIsANoReturnWhenOrganizedAndAnErrorOtherwise) {
  auto c = organized_scan();
  c.points[7].x = std::numeric_limits<float>::quiet_NaN();
  const auto dir = test::temp_dir("pcd_nan");
  io::write_pcd(dir / "org.pcd", c);
  const auto back = io::read_pcd(dir / "org.pcd");
  EXPECT_FALSE(back.points[7].is_valid());
  EXPECT_EQ(back.points[7].x, 0.f);
  EXPECT_EQ(back.valid_count(), c.size() - 2);

  PointCloud u;
  u.push_back({1, 2, 3});
  u.push_back({std::numeric_limits<float>::quiet_NaN(), 2, 3});
  io::write_pcd(dir / "unorg.pcd", u);
  try {
    io::read_pcd(dir / "unorg.pcd");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("unorg.pcd"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("point 1"), std::string::npos);
  }
}

TEST(Pcd, RealOuster128Scan) {
  FIELDLIDAR_REQUIRE_DATA("pcd_os128/000000.pcd");
  const auto c = io::read_pcd(test::data_file("pcd_os128/000000.pcd"));
  ASSERT_EQ(c.size(), 240000u);
  EXPECT_EQ(c.width, 1875u);
  EXPECT_EQ(c.height, 128u);
  EXPECT_TRUE(c.is_organized());
  EXPECT_EQ(c.ring_count(), 128u);
  EXPECT_TRUE(c.fields.time && c.fields.intensity && c.fields.ring);
  // `timestamp` is float64 UNIX time in s (2021-09-11); zero-stamped cells are no-returns.
  EXPECT_NEAR(c.stamp_s, 1631322303.47, 0.01);
  float tmax = 0.f;
  for (const auto& p : c.points) tmax = std::max(tmax, p.time);
  EXPECT_GT(tmax, 0.09f);  // one 10 Hz sweep
  EXPECT_LT(tmax, 0.11f);
  EXPECT_GT(c.valid_count(), 200000u);
  EXPECT_LT(c.valid_count(), 240000u);
}
