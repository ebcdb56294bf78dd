#pragma once
/// \file The motion streams the odometry takes besides the LiDAR: IMU and wheel speeds, both in
/// the robot's base frame.

#include <Eigen/Core>

#include "fieldlidar/core/imu_sample.hpp"

namespace fieldlidar::odometry {

using fieldlidar::ImuSample;  // core/imu_sample.hpp

/// Body speeds of a wheeled base measured by its encoders (differential drive: forward speed
/// along base x and yaw rate about base z).
struct WheelSample {
  double stamp_s = 0.0;
  double linear_m_s = 0.0;
  double yaw_rate_rad_s = 0.0;
};

}  // namespace fieldlidar::odometry
