// What LidarOdometry refuses up front: IMU and wheel samples holding NaN or inf (they would be
// integrated into every later pose), and localisation in an empty map or from a NaN pose.

#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/odometry/lidar_odometry.hpp"

namespace fieldlidar::odometry {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

TEST(OdometryInput, NonFiniteImuAndWheelSamplesAreRefused) {
  LidarOdometry odo(SensorModel::vlp16());
  std::vector<ImuSample> imu(3);
  for (int i = 0; i < 3; ++i) imu[i].stamp_s = 0.01 * i, imu[i].accel_m_s2.z() = 9.81;
  imu[2].gyro_rad_s.x() = kNaN;
  EXPECT_NE(
      error_of([&] { odo.add_imu(imu); }).find("IMU sample 2 (stamp 0.02 s) holds NaN or inf"),
      std::string::npos);
  std::vector<WheelSample> wheels = {{0.0, 0.5, 0.0}, {0.02, kInf, 0.0}};
  EXPECT_NE(error_of([&] { odo.add_wheels(wheels); }).find("wheel sample 1"), std::string::npos);
  imu[2].gyro_rad_s.x() = 0.0;
  EXPECT_NO_THROW(odo.add_imu(imu));
}

TEST(OdometryInput, EmptyMapAndNonFiniteInitialPoseAreRefused) {
  LidarOdometry odo(SensorModel::vlp16());
  EXPECT_NE(error_of([&] { odo.set_map(LocalMap(), Pose::Identity()); }).find("no points"),
            std::string::npos);
  PointCloud cloud;
  cloud.points.push_back({});
  cloud.points.back().x = 3.f;
  const LocalMap map = LocalMap::from_cloud(cloud);
  ASSERT_GT(map.size(), 0u);
  Pose nan_pose = Pose::Identity();
  nan_pose.translation().x() = kNaN;
  EXPECT_NE(error_of([&] { odo.set_map(map, nan_pose); }).find("not finite"), std::string::npos);
  EXPECT_NO_THROW(odo.set_map(map, Pose::Identity()));
}

}  // namespace
}  // namespace fieldlidar::odometry
