#include <fstream>
#include <limits>

#include <gtest/gtest.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/ply.hpp"
#include "test_data.hpp"

using namespace fieldlidar;

namespace {
PointCloud sample() {
  PointCloud c;
  c.fields = {.intensity = true, .ring = true, .time = true, .label = true};
  for (int i = 0; i < 200; ++i) {
    Point p{0.01f * i - 1.f, 3.3f - 0.02f * i, 0.5f * (i % 7), float(i % 255)};
    p.ring = static_cast<std::uint16_t>(i % 32);
    p.time = 1e-4f * i;
    c.push_back(p, static_cast<std::uint32_t>(i % 5));
  }
  return c;
}
}  // namespace

TEST(Ply, RoundTripBinaryAndAscii) {
  const auto c = sample();
  const auto dir = test::temp_dir("ply_rt");
  io::write_ply(dir / "b.ply", c);
  io::write_ply(dir / "a.ply", c, {.binary = false});
  for (const char* f : {"b.ply", "a.ply"}) {
    SCOPED_TRACE(f);
    const auto back = io::read_ply(dir / f);
    ASSERT_EQ(back.size(), c.size());
    EXPECT_EQ(back.fields, c.fields);
    EXPECT_EQ(back.labels, c.labels);
    for (std::size_t i = 0; i < c.size(); ++i) {
      // Binary is exact; ascii prints float32 with 9 significant digits, which round-trips.
      const float tol = 0.f;
      EXPECT_NEAR(back.points[i].x, c.points[i].x, tol);
      EXPECT_NEAR(back.points[i].y, c.points[i].y, tol);
      EXPECT_NEAR(back.points[i].z, c.points[i].z, tol);
      EXPECT_EQ(back.points[i].intensity, c.points[i].intensity);
      EXPECT_EQ(back.points[i].ring, c.points[i].ring);
      EXPECT_NEAR(back.points[i].time, c.points[i].time, tol);
    }
  }
  EXPECT_THROW(io::write_ply(dir / "b.ply", c), Error);
}

TEST(Ply, HandWrittenAsciiWithCloudCompareIntensity) {
  const auto dir = test::temp_dir("ply_cc");
  std::ofstream(dir / "cc.ply") << "ply\nformat ascii 1.0\ncomment made by hand\n"
                                   "element vertex 2\nproperty float x\nproperty float y\n"
                                   "property float z\nproperty float scalar_Intensity\n"
                                   "end_header\n1 2 3 40\n-1 -2 -3 50\n";
  const auto c = io::read_ply(dir / "cc.ply");
  ASSERT_EQ(c.size(), 2u);
  EXPECT_TRUE(c.fields.intensity);
  EXPECT_EQ(c.points[1].intensity, 50.f);
  EXPECT_EQ(c.points[1].z, -3.f);
}

TEST(Ply, NanCoordinateIsAnError) {
  auto c = sample();
  c.points[10].y = std::numeric_limits<float>::quiet_NaN();
  const auto dir = test::temp_dir("ply_nan");
  io::write_ply(dir / "n.ply", c);
  try {
    io::read_ply(dir / "n.ply");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("n.ply"), std::string::npos);
  }
}
