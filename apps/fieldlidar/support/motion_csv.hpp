#pragma once
// The IMU and wheel CSV files `fieldlidar odometry` reads (a simulator folder's imu.csv and
// odom.csv, or the user's own): every cell a finite number, or an error naming file, line and
// column, since one NaN there turns every later pose into NaN.

#include <filesystem>
#include <vector>

#include "fieldlidar/core/imu_sample.hpp"
#include "fieldlidar/odometry/motion_input.hpp"

namespace fieldlidar::app {

/// Rows of stamp_s, gyro xyz (rad/s), accel xyz (m/s^2) after a header line.
std::vector<ImuSample> read_imu_csv(const std::filesystem::path& path);

/// Wheel speeds after a header line: the simulator's odom.csv (stamp_s, left_m_s, right_m_s,
/// left_rad_s, right_rad_s, linear_m_s, yaw_rate_rad_s, ...) or stamp,linear_m_s,yaw_rate_rad_s.
std::vector<odometry::WheelSample> read_wheels_csv(const std::filesystem::path& path);

}  // namespace fieldlidar::app
