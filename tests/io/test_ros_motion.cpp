// ROS1 motion messages: sensor_msgs/Imu, nav_msgs/Odometry and geometry_msgs/TwistStamped from
// synthetic serialized bytes, and a whole nav_msgs/Odometry topic of a real bag.
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/rosbag_reader.hpp"
#include "test_data.hpp"

namespace fieldlidar {
namespace {

/// ROS1 wire format writer: little-endian scalars, uint32-prefixed strings.
struct Wire {
  std::vector<std::uint8_t> b;
  void put(const void* p, std::size_t n) {
    const auto* c = static_cast<const std::uint8_t*>(p);
    b.insert(b.end(), c, c + n);
  }
  void u32(std::uint32_t v) { put(&v, 4); }
  void f64(double v) { put(&v, 8); }
  void str(const std::string& s) { u32(std::uint32_t(s.size())), put(s.data(), s.size()); }
  void header(std::uint32_t sec, std::uint32_t nsec, const std::string& frame) {
    u32(7), u32(sec), u32(nsec), str(frame);
  }
  void doubles(std::initializer_list<double> v) {
    for (double x : v) f64(x);
  }
  void zeros(int n) {
    for (int i = 0; i < n; ++i) f64(0.0);
  }
};

std::vector<std::uint8_t> imu_bytes() {
  Wire w;
  w.header(1000, 500000000, "imu_link");
  w.doubles({0, 0, 0, 1});  // orientation x y z w
  w.zeros(9);
  w.doubles({0.01, -0.02, 0.3});  // angular velocity (rad/s)
  w.zeros(9);
  w.doubles({0.1, 0.2, 9.81});  // linear acceleration (m/s^2)
  w.zeros(9);
  return w.b;
}

std::vector<std::uint8_t> odometry_bytes() {
  Wire w;
  w.header(42, 250000000, "odom");
  w.str("base_link");
  const double half = 0.5 * M_PI / 2;                 // yaw 90 deg
  w.doubles({1.5, -2.0, 0.1});                        // position
  w.doubles({0, 0, std::sin(half), std::cos(half)});  // orientation x y z w
  w.zeros(36);
  w.doubles({0.8, 0.0, 0.0, 0.0, 0.0, -0.25});  // twist: linear, angular
  w.zeros(36);
  return w.b;
}

std::vector<std::uint8_t> twist_stamped_bytes() {
  Wire w;
  w.header(5, 0, "base_link");
  w.doubles({0.4, 0.0, 0.0, 0.0, 0.0, 0.1});
  return w.b;
}

TEST(RosMotion, ImuWireFormat) {
  const auto bytes = imu_bytes();
  const auto s = io::parse_imu(bytes);
  EXPECT_DOUBLE_EQ(s.stamp_s, 1000.5);
  EXPECT_DOUBLE_EQ(s.gyro_rad_s.z(), 0.3);
  EXPECT_DOUBLE_EQ(s.gyro_rad_s.y(), -0.02);
  EXPECT_DOUBLE_EQ(s.accel_m_s2.z(), 9.81);
  EXPECT_DOUBLE_EQ(s.accel_m_s2.x(), 0.1);
  auto cut = bytes;
  cut.resize(cut.size() - 1);
  EXPECT_THROW(io::parse_imu(cut), Error);
}

TEST(RosMotion, OdometryWireFormat) {
  const auto bytes = odometry_bytes();
  const auto s = io::parse_odometry(bytes);
  EXPECT_DOUBLE_EQ(s.stamp_s, 42.25);
  EXPECT_DOUBLE_EQ(s.pose.translation().x(), 1.5);
  EXPECT_DOUBLE_EQ(s.pose.translation().y(), -2.0);
  const Eigen::Vector3d x_axis = s.pose.linear().col(0);
  EXPECT_NEAR(x_axis.y(), 1.0, 1e-12);  // yaw 90 deg
  EXPECT_DOUBLE_EQ(s.linear_m_s.x(), 0.8);
  EXPECT_DOUBLE_EQ(s.angular_rad_s.z(), -0.25);
  auto cut = bytes;
  cut.resize(cut.size() - 8);
  EXPECT_THROW(io::parse_odometry(cut), Error);
}

TEST(RosMotion, TwistStampedWireFormat) {
  const auto bytes = twist_stamped_bytes();
  const auto s = io::parse_twist_stamped(bytes);
  EXPECT_DOUBLE_EQ(s.stamp_s, 5.0);
  EXPECT_DOUBLE_EQ(s.linear_m_s.x(), 0.4);
  EXPECT_DOUBLE_EQ(s.angular_rad_s.z(), 0.1);
  EXPECT_TRUE(s.pose.isApprox(Pose::Identity()));
  auto cut = bytes;
  cut.resize(cut.size() - 4);
  EXPECT_THROW(io::parse_twist_stamped(cut), Error);
}

const char* kTracking = "legs_2d_tracking/general_tracking_moving_1.bag";

TEST(RosMotion, OdometryTopicOfARealBag) {
  FIELDLIDAR_REQUIRE_DATA(kTracking);
  const auto path = test::data_file(kTracking);
  const auto odom = io::read_odometry_topic(path, "/odom");
  ASSERT_EQ(odom.size(), 11561u);  // every message of the topic (fieldlidar info)
  double path_m = 0, max_speed = 0;
  for (std::size_t i = 1; i < odom.size(); ++i) {
    ASSERT_GE(odom[i].stamp_s, odom[i - 1].stamp_s);
    path_m += (odom[i].pose.translation() - odom[i - 1].pose.translation()).norm();
    max_speed = std::max(max_speed, std::abs(odom[i].linear_m_s.x()));
  }
  const double span_s = odom.back().stamp_s - odom.front().stamp_s;
  // ~100 Hz over the recording's 116 s, a robot driving at walking pace.
  EXPECT_GT(span_s, 110.0);
  EXPECT_LT(span_s, 125.0);
  EXPECT_GT(path_m, 5.0);
  EXPECT_LT(path_m, 200.0);
  EXPECT_GT(max_speed, 0.1);
  EXPECT_LT(max_speed, 2.0);
  // Wrong types and missing topics name the bag's topics.
  try {
    io::read_imu_topic(path, "/odom");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("not sensor_msgs/Imu"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("/scan"), std::string::npos) << e.what();
  }
  EXPECT_THROW(io::read_odometry_topic(path, "/scan"), Error);
  EXPECT_THROW(io::read_odometry_topic(path, "/no_such_topic"), Error);
}

TEST(RosMotion, TfMessageWireFormat) {
  Wire w;
  w.u32(2);
  for (int k = 0; k < 2; ++k) {
    w.header(10, 0, "base_link");
    w.str(k ? "left_laser" : "rear_laser");
    w.doubles({0.85, 0.235 * k, 0.0, 0, 0, 0, 1});
  }
  const auto tfs = io::parse_tf_message(w.b);
  ASSERT_EQ(tfs.size(), 2u);
  EXPECT_EQ(tfs[1].parent, "base_link");
  EXPECT_EQ(tfs[1].child, "left_laser");
  EXPECT_DOUBLE_EQ(tfs[1].T_parent_child.translation().y(), 0.235);
  auto cut = w.b;
  cut.resize(cut.size() - 8);
  EXPECT_THROW(io::parse_tf_message(cut), Error);
}

TEST(RosMotion, LaserMountFromTheBagsTf) {
  FIELDLIDAR_REQUIRE_DATA(kTracking);
  const auto path = test::data_file(kTracking);
  EXPECT_EQ(io::first_frame_id(path, "/scan"), "left_laser");
  const auto odom = io::read_odometry_topic(path, "/odom");
  EXPECT_EQ(odom.front().child_frame_id, "/base_link");
  // The odometry names "/base_link", /tf "base_link": compared without the leading '/'.
  const auto T = io::read_mount_transform(path, "/base_link", "left_laser");
  ASSERT_TRUE(T);
  EXPECT_NEAR(T->translation().x(), 0.850, 0.001);
  EXPECT_NEAR(T->translation().y(), 0.235, 0.001);
  EXPECT_NEAR(yaw_of(*T) * 180 / M_PI, 42.1, 0.1);
  EXPECT_FALSE(io::read_mount_transform(path, "base_link", "no_such_frame"));
}

}  // namespace
}  // namespace fieldlidar
