#pragma once
/// \file One IMU reading, as recorded (io), simulated (sim) and consumed (odometry).

#include <Eigen/Core>

namespace fieldlidar {

/// One IMU reading in the IMU's own frame: angular rate and specific force (gravity included: an
/// IMU at rest reads about +9.81 m/s^2 on its up axis).
struct ImuSample {
  double stamp_s = 0.0;
  Eigen::Vector3d gyro_rad_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel_m_s2 = Eigen::Vector3d::Zero();
};

}  // namespace fieldlidar
