#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/kitti_bin.hpp"
#include "test_data.hpp"

using namespace fieldlidar;

TEST(KittiBin, RoundTrip) {
  PointCloud c;
  for (int i = 0; i < 100; ++i) c.push_back({0.1f * i, -0.2f * i, 1.5f, float(i)});
  const auto dir = test::temp_dir("kitti_rt");
  io::write_kitti_bin(dir / "a.bin", c);
  const auto back = io::read_kitti_bin(dir / "a.bin");
  ASSERT_EQ(back.size(), c.size());
  for (std::size_t i = 0; i < c.size(); ++i) {
    EXPECT_EQ(back.points[i].x, c.points[i].x);
    EXPECT_EQ(back.points[i].intensity, c.points[i].intensity);
  }
  // Existing files are not replaced unless asked.
  EXPECT_THROW(io::write_kitti_bin(dir / "a.bin", c), Error);
  EXPECT_NO_THROW(io::write_kitti_bin(dir / "a.bin", c, {.overwrite = true}));
}

TEST(KittiBin, BadInputGivesClearErrors) {
  std::vector<std::byte> truncated(16 * 3 + 5);
  EXPECT_THROW(io::parse_kitti_bin(truncated, "t.bin"), Error);
  EXPECT_TRUE(io::parse_kitti_bin({}, "empty.bin").empty());
  std::vector<float> nan_pts = {1, 2, std::numeric_limits<float>::quiet_NaN(), 0};
  std::vector<std::byte> bytes(nan_pts.size() * 4);
  std::memcpy(bytes.data(), nan_pts.data(), bytes.size());
  try {
    io::parse_kitti_bin(bytes, "nan.bin");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("nan.bin"), std::string::npos);
  }
  EXPECT_THROW(io::read_kitti_bin("/nonexistent/x.bin"), Error);
}

TEST(KittiBin, RealKittiFrame) {
  FIELDLIDAR_REQUIRE_DATA("kitti00/000000.bin");
  const auto c = io::read_kitti_bin(test::data_file("kitti00/000000.bin"));
  EXPECT_EQ(c.size(), 124668u);
  const auto b = compute_bounds(c);
  EXPECT_LT(b.min.z(), -1.5);  // the road below a 1.73 m high sensor
  EXPECT_GT(b.max.x(), 50.0);
}
