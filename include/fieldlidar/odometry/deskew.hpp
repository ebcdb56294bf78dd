#pragma once
/// \file seed 002, step a: the lidar's motion during one sweep (from the IMU and wheel speeds, or
/// a constant velocity) and the sweep re-projected onto the pose at its start.

#include <optional>
#include <span>
#include <vector>

#include "fieldlidar/core/point_cloud.hpp"
#include "fieldlidar/core/pose.hpp"
#include "fieldlidar/odometry/motion_input.hpp"

namespace fieldlidar::odometry {

struct DeskewConfig {
  bool enabled = true;
  bool use_imu = true;     ///< gyro rotation (and accelerometer without wheels) when given
  bool use_wheels = true;  ///< wheel forward speed when given
  /// The IMU stream counts as stopped when two samples (or the sweep's ends and the nearest
  /// sample) are farther apart than this (s); the motion falls back to wheels / constant velocity.
  double max_imu_gap_s = 0.05;
  double max_wheel_gap_s = 0.1;  ///< same for the wheel stream (s)
  /// Without IMU or wheels, de-skew with the last sweep-to-sweep motion. Only for a LiDAR-only
  /// run: where given streams do not cover a sweep (they lag, or stopped) it is not de-skewed,
  /// as before (the follow loop's streams arrive one period at a time).
  bool constant_velocity = true;
  /// ... when the last motion spans at most this many sweep periods. On a 2 Hz handheld yaw sweep
  /// (every 5th sweep) the motion over 0.5 s has little to do with that within the next sweep:
  /// its worst frame went from 3.8 to 7.9 deg with it.
  double constant_velocity_max_period_factor = 1.5;
  /// The constant-velocity de-skew moves by the mean of the last two sweep-to-sweep motions, not
  /// the last one (the pose prior keeps the last). A pose error of one sweep enters the next
  /// velocity with one sign and the one after with the other; through the de-skew it came back
  /// as the next pose error and rang from sweep to sweep (steps alternating 0.35 / 0.37 m at
  /// 0.36 m per sweep); the mean of two cancels that. LiDAR only, RPE per frame, last motion ->
  /// mean of two: simulated HDL-64E at 3.6 m/s, skewed sweeps with times, forest 1.20 -> 0.58
  /// cm, terrain 0.63 -> 0.48, lawn 1.50 -> 1.08 (IMU + wheels: 0.61, 0.53, 1.11); terrain seed
  /// 23 (VLP-16, 300 sweeps) 1.64 cm / 0.078 deg -> 1.14 / 0.059, drift 0.437 -> 0.408 %;
  /// greenhouse frames 0-299 0.45 cm / 0.042 deg -> 0.40 / 0.034, frames 600-1199 0.59 / 0.079
  /// -> 0.51 / 0.070, ATE 21.5 -> 19.7 mm.
  bool velocity_from_two_sweeps = true;
  /// Re-project the sweep onto the pose at mid-sweep, register that pose, and report the start
  /// pose from it. A velocity error e then shifts the points by e (t - T/2), zero on average, so
  /// the registered pose does not depend on it. Referred to the start, the same error shifts the
  /// sweep by e T / 2 on average, the registration absorbs that into the pose, the next velocity
  /// takes it up with the opposite sign, and a constant-velocity de-skew oscillates and diverges
  /// (greenhouse, LiDAR only: RPE 45 cm per frame).
  /// Applies to the constant-velocity de-skew only: with IMU/wheel motion the sweep stays
  /// referred to its start (at mid-sweep the follow loop's boundary Hausdorff rose from 0.29 to
  /// 0.34 m and an occlusion stop came 9 frames late, though the odometry ATE improved; not
  /// understood yet).
  bool mid_sweep_reference = true;
  Pose T_base_lidar = Pose::Identity();  ///< lidar in the base (IMU, wheel) frame
  /// Without per-point times, a spinning sensor's point time is taken from its azimuth
  /// (0 = off): the sweep period (s). By default the sweep starts and ends behind the sensor
  /// and turns clockwise seen from above, as a Velodyne does.
  double azimuth_time_period_s = 0.0;
  /// Where such a sweep starts (deg, counter-clockwise from +x; 180 = behind) and whether it
  /// turns clockwise seen from above. KITTI's HDL-64E files list each ring from the front
  /// (0 deg) counter-clockwise. On kitti_tracking0000 every start and sense (180 / 0 deg,
  /// clockwise or not) de-skewed by the constant velocity gave a rotation RPE of 0.10-0.12 deg
  /// per frame against 0.048 without times (translation 1.6-2.0 cm against 1.59). Simulated
  /// HDL-64E sweeps at that speed de-skewed so gain when they are skewed (RPE as with IMU +
  /// wheels) and lose when they are not (rotation RPE x 1.7-2.7): KITTI's behave as already
  /// motion-compensated (test_odometry_hdl64_scale.cpp).
  double azimuth_start_deg = 180.0;
  bool azimuth_clockwise = true;
};

/// Poses of the lidar during one sweep relative to its pose at the sweep start, T_start_t,
/// sampled at increasing time offsets (s from the sweep start) and interpolated between.
class SweepMotion {
 public:
  SweepMotion() = default;
  /// Constant velocity: T_start_t = interpolate(I, T_start_next, t / period_s).
  static SweepMotion constant_velocity(const Pose& T_start_next, double period_s);
  void push_back(double t_s, const Pose& T_start_t);
  /// Pose at time offset t (clamped to the samples; identity when there is none).
  Pose at(double t_s) const;
  /// Relative pose at the last sample.
  Pose last() const { return poses_.empty() ? Pose::Identity() : poses_.back(); }
  double last_time_s() const { return times_.empty() ? 0.0 : times_.back(); }
  bool empty() const { return poses_.empty(); }

 private:
  std::vector<double> times_;
  std::vector<Pose> poses_;
};

/// Where the motion of a sweep came from.
enum class MotionSource { kConstantVelocity, kImuWheels, kImu, kWheels };

/// The lidar's motion over [t0_s, t1_s] from the IMU (rotation from the gyro) and the wheels
/// (forward speed); without wheels the velocity `v0_lidar_m_s` (lidar frame, at t0) is carried
/// on with the accelerometer, gravity `g_base0_m_s2` given in the base frame at t0 (as the
/// accelerometer reads it at rest). nullopt when neither stream covers the interval without a gap.
struct ImuWheelMotion {
  SweepMotion motion;
  MotionSource source = MotionSource::kConstantVelocity;
};
std::optional<ImuWheelMotion> integrate_motion(std::span<const ImuSample> imu,
                                               std::span<const WheelSample> wheels, double t0_s,
                                               double t1_s, const Eigen::Vector3d& v0_lidar_m_s,
                                               const Eigen::Vector3d& g_base0_m_s2,
                                               const DeskewConfig& config);

/// Point time offsets (s from the sweep start): the time field when the cloud has one, else from
/// the azimuth when config.azimuth_time_period_s > 0, else all zero.
std::vector<float> point_times(const PointCloud& cloud, const DeskewConfig& config);

/// Every point re-projected onto the pose at time `reference_s` of the sweep:
/// p_ref = T_start_ref^-1 * T_start_t(t) * p. Invalid points are kept as they are.
PointCloud deskew(const PointCloud& cloud, std::span<const float> times_s,
                  const SweepMotion& motion, double reference_s = 0.0);

}  // namespace fieldlidar::odometry
