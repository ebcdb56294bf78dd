// ROS1 bags: LaserScan as a one-ring cloud, PoseArray, topic counts, topic errors, message bytes.
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>

#include <gtest/gtest.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/rosbag_reader.hpp"
#include "test_data.hpp"

namespace fieldlidar {
namespace {

const char* kPositive = "legs_2d/positive_1_extracted.bag";
const char* kNegative = "legs_2d/negative_2.bag";

TEST(Rosbag, TopicCountsOfTheAnnotatedLegBag) {
  FIELDLIDAR_REQUIRE_DATA(kPositive);
  const auto counts = io::bag_topic_counts(test::data_file(kPositive));
  ASSERT_TRUE(counts.count("/training_scan"));
  ASSERT_TRUE(counts.count("/leg_cluster_positions"));
  EXPECT_GT(counts.at("/training_scan"), 10u);
  // One annotation per scan.
  EXPECT_EQ(counts.at("/leg_cluster_positions"), counts.at("/training_scan"));
}

TEST(Rosbag, LaserScansBecomeOneRingCloudsInAngleOrder) {
  FIELDLIDAR_REQUIRE_DATA(kPositive);
  auto src = io::FrameSource::open(test::data_file(kPositive));  // the only scan topic
  EXPECT_EQ(src->format(), "rosbag");
  std::size_t n = 0;
  double last_stamp = 0;
  while (auto f = src->next()) {
    const auto& c = f->cloud;
    EXPECT_EQ(f->topic, "/training_scan");
    ASSERT_GT(c.size(), 50u);
    EXPECT_EQ(c.ring_count(), 1u);
    EXPECT_GE(f->stamp_s, last_stamp);
    last_stamp = f->stamp_s;
    double prev_angle = -10;
    for (const auto& p : c.points) {
      ASSERT_EQ(p.ring, 0);
      ASSERT_EQ(p.z, 0.f);
      const double a = std::atan2(p.y, p.x);
      ASSERT_GT(a, prev_angle - 1e-6);  // increasing scan angle (scan within -pi..pi)
      prev_angle = a;
      const double r = std::hypot(p.x, p.y);
      ASSERT_GT(r, 0.0);
      ASSERT_LT(r, 60.0);
    }
    ++n;
  }
  EXPECT_EQ(n, io::bag_topic_counts(test::data_file(kPositive)).at("/training_scan"));
}

TEST(Rosbag, PoseArraysHoldTheAnnotatedLegPositions) {
  FIELDLIDAR_REQUIRE_DATA(kPositive);
  const auto arrays = io::read_pose_arrays(test::data_file(kPositive), "/leg_cluster_positions");
  auto scans = io::FrameSource::open(test::data_file(kPositive));
  ASSERT_FALSE(arrays.empty());
  // Annotation i belongs to scan i (recorded in step); every annotated leg lies on the scan:
  // within 0.25 m of one of its returns (a leg is ~0.1-0.2 m across).
  std::size_t legs = 0;
  for (const auto& a : arrays) {
    const auto scan = scans->next();
    ASSERT_TRUE(scan);
    for (const auto& pose : a.poses) {
      ++legs;
      double best = 1e9;
      for (const auto& p : scan->cloud.points)
        best =
            std::min(best, std::hypot(p.x - pose.translation().x(), p.y - pose.translation().y()));
      EXPECT_LT(best, 0.25) << "scan " << scan->index;
    }
  }
  EXPECT_GT(legs, arrays.size() / 2);
  EXPECT_THROW(io::read_pose_arrays(test::data_file(kPositive), "/training_scan"), Error);
}

TEST(Rosbag, MissingOrAmbiguousTopicListsTheTopics) {
  FIELDLIDAR_REQUIRE_DATA(kNegative);
  io::SourceOptions o;
  try {
    io::FrameSource::open(test::data_file(kNegative), o);
    FAIL() << "three scan topics: must ask for one";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("--topic"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("/rear_scan"), std::string::npos) << e.what();
  }
  o.topic = "/front_scan";
  try {
    io::FrameSource::open(test::data_file(kNegative), o);
    FAIL() << "a missing topic must be refused";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no topic '/front_scan'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("/left_scan"), std::string::npos) << e.what();
  }
  o.topic = "/left_scan";
  auto src = io::FrameSource::open(test::data_file(kNegative), o);
  const auto f = src->next();
  ASSERT_TRUE(f);
  EXPECT_EQ(f->topic, "/left_scan");
}

/// Serializes a LaserScan by hand in the ROS1 wire format.
std::vector<std::uint8_t> laser_scan_bytes(const std::vector<float>& ranges) {
  std::vector<std::uint8_t> b;
  auto put = [&](const void* p, std::size_t n) {
    const auto* c = static_cast<const std::uint8_t*>(p);
    b.insert(b.end(), c, c + n);
  };
  const std::uint32_t seq = 1, sec = 100, nsec = 500000000, frame_len = 4;
  put(&seq, 4), put(&sec, 4), put(&nsec, 4), put(&frame_len, 4), put("scan", 4);
  const float head[7] = {-1.0f, 1.0f, 0.5f, 0.001f, 0.1f, 0.2f, 10.0f};
  put(head, sizeof head);
  const std::uint32_t n = std::uint32_t(ranges.size()), zero = 0;
  put(&n, 4), put(ranges.data(), 4 * ranges.size()), put(&zero, 4);
  return b;
}

TEST(Rosbag, LaserScanWireFormat) {
  const auto bytes = laser_scan_bytes({1.0f, 0.1f, 2.0f, std::nanf(""), 20.0f});
  const auto c = io::parse_laser_scan(bytes);
  EXPECT_DOUBLE_EQ(c.stamp_s, 100.5);
  ASSERT_EQ(c.size(), 2u);  // 0.1 < range_min, NaN, 20 > range_max skipped
  EXPECT_NEAR(c.points[0].x, std::cos(-1.0), 1e-6);
  EXPECT_NEAR(c.points[0].y, std::sin(-1.0), 1e-6);
  EXPECT_NEAR(c.points[1].x, 2 * std::cos(0.0), 1e-6);
  EXPECT_NEAR(c.points[1].time, 0.002, 1e-7);  // beam 2 of the scan
  auto cut = bytes;
  cut.resize(cut.size() - 9);
  EXPECT_THROW(io::parse_laser_scan(cut), Error);
  EXPECT_THROW(io::parse_point_cloud2(bytes), Error);
}

/// PointCloud2 in the Ouster driver's layout: x y z intensity (float32), t (uint32 ns), ring
/// (uint16), 2 x 2 organized, one NaN point.
std::vector<std::uint8_t> point_cloud2_bytes() {
  std::vector<std::uint8_t> b;
  auto put = [&](const void* p, std::size_t n) {
    const auto* c = static_cast<const std::uint8_t*>(p);
    b.insert(b.end(), c, c + n);
  };
  auto u32 = [&](std::uint32_t v) { put(&v, 4); };
  auto str = [&](const std::string& s) { u32(std::uint32_t(s.size())), put(s.data(), s.size()); };
  u32(3), u32(200), u32(250000000), str("os_lidar");
  u32(2), u32(2);  // height, width
  struct F {
    const char* name;
    std::uint32_t offset;
    std::uint8_t type;
  };
  const F fields[] = {{"x", 0, 7},          {"y", 4, 7},  {"z", 8, 7},
                      {"intensity", 12, 7}, {"t", 16, 6}, {"ring", 20, 4}};
  u32(6);
  for (const auto& f : fields) {
    str(f.name), u32(f.offset);
    put(&f.type, 1);
    u32(1);
  }
  const std::uint8_t big_endian = 0;
  put(&big_endian, 1);
  const std::uint32_t step = 24;
  u32(step), u32(2 * step), u32(4 * step);
  for (int i = 0; i < 4; ++i) {
    const float xyz[4] = {i == 3 ? std::nanf("") : float(i + 1), 2.f, 3.f, 10.f * i};
    put(xyz, 16);
    u32(std::uint32_t(i) * 1000000u);  // 1 ms apart
    const std::uint16_t ring = std::uint16_t(i / 2), pad = 0;
    put(&ring, 2), put(&pad, 2);
  }
  const std::uint8_t dense = 0;
  put(&dense, 1);
  return b;
}

TEST(Rosbag, PointCloud2WireFormatWithRingAndTime) {
  const auto bytes = point_cloud2_bytes();
  const auto c = io::parse_point_cloud2(bytes);
  EXPECT_DOUBLE_EQ(c.stamp_s, 200.25);
  ASSERT_EQ(c.size(), 4u);  // organized: the NaN point stays as a zero "no return"
  EXPECT_EQ(c.width, 2u);
  EXPECT_EQ(c.height, 2u);
  EXPECT_TRUE(c.fields.ring && c.fields.time && c.fields.intensity);
  EXPECT_FLOAT_EQ(c.points[1].x, 2.f);
  EXPECT_FLOAT_EQ(c.points[2].intensity, 20.f);
  EXPECT_EQ(c.points[2].ring, 1);
  EXPECT_NEAR(c.points[2].time, 0.002, 1e-9);
  EXPECT_FALSE(c.points[3].is_valid());
  auto cut = bytes;
  cut.resize(cut.size() - 30);
  EXPECT_THROW(io::parse_point_cloud2(cut), Error);
}

TEST(Rosbag, DamagedMessageRecordIsAnErrorNotACrash) {
  // One byte of a message record's header length changed: the length then read for its data
  // is far larger than its chunk, which rosbag_storage would copy from regardless.
  const char* kBag = "legs_2d/positive_2_extracted.bag";
  FIELDLIDAR_REQUIRE_DATA(kBag);
  std::ifstream in(test::data_file(kBag), std::ios::binary);
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  // A message data record's header: 38 bytes (op, conn, time), its op field 0x02; the first
  // after byte 78900 is /training_scan's message 18.
  const std::string op_field("\x04\0\0\0op=\x02", 8);
  std::size_t damaged = 0;
  for (std::size_t i = 78900; i + 50 < bytes.size() && !damaged; ++i)
    if (bytes[i] == 0x26 && bytes[i + 1] == 0 && bytes[i + 2] == 0 && bytes[i + 3] == 0 &&
        std::string(bytes.data() + i + 4, 38).find(op_field) != std::string::npos) {
      bytes[i] = 0x74;
      damaged = i;
    }
  ASSERT_GT(damaged, 0u);
  const auto file = test::temp_dir("rosbag_damaged") / "damaged.bag";
  std::ofstream(file, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
  try {
    auto src = io::FrameSource::open(file);
    while (src->next()) {
    }
    FAIL() << "a damaged record at byte " << damaged << " must be an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("damaged.bag"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("the bag is damaged"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace fieldlidar
