#pragma once
/// \file The motion streams the odometry takes besides the LiDAR: IMU and wheel speeds, both in
/// the robot's base frame.

#include <Eigen/Core>

namespace fieldlidar::odometry {

/// One IMU reading in the base frame: angular rate and specific force (gravity included: a robot
/// at rest reads about +9.81 m/s^2 on z).
struct ImuSample {
  double stamp_s = 0.0;
  Eigen::Vector3d gyro_rad_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel_m_s2 = Eigen::Vector3d::Zero();
};

/// Body speeds of a wheeled base measured by its encoders (differential drive: forward speed
/// along base x and yaw rate about base z).
struct WheelSample {
  double stamp_s = 0.0;
  double linear_m_s = 0.0;
  double yaw_rate_rad_s = 0.0;
};

}  // namespace fieldlidar::odometry
