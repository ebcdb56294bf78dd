#pragma once
// The robot's motion as a recording gives it, for the commands that replay recorded scans (follow
// --replay, legs, eval-tracking): a bag's nav_msgs/Odometry topic, the scan's mount on the base
// read from the bag's /tf, or a TUM pose file of the sensor (e.g. a simulator folder's
// poses_tum.txt).

#include <cstddef>
#include <filesystem>
#include <string>

#include "fieldlidar/core/pose.hpp"

namespace fieldlidar::app {

struct RecordedMotion {
  Trajectory poses;  ///< of the base (odometry topic) or of the sensor (TUM file)
  Pose T_base_sensor = Pose::Identity();
  std::string mount_from = "none (the sensor is the base)";
  /// The base pose at `stamp_s`, held at the ends of the recorded span; a stamp more than
  /// kSpanSlackS outside it is counted (frames_outside).
  Pose base_at(double stamp_s);
  /// The sensor pose at `stamp_s` (base_at * T_base_sensor).
  Pose sensor_at(double stamp_s) { return base_at(stamp_s) * T_base_sensor; }
  /// Warns (by `warn`) when frames fell outside the recorded span: they were placed at its
  /// nearest end, as if the robot stood there.
  void warn_outside(const std::string& odom) const;

  static constexpr double kSpanSlackS = 0.5;  ///< a recording's streams start a little apart
  std::size_t frames_outside = 0;
};

/// `odom` names a TUM pose file when `input` is not a bag (a simulator folder, a capture), else a
/// nav_msgs/Odometry topic of the bag `input`, whose scans on `scan_topic` ("" = the bag's only
/// scan topic) are mounted on the odometry's child frame by the bag's /tf (a warning, by `warn`,
/// when it has none: the scans are taken as seen from the base's origin). Throws
/// fieldlidar::Error naming a missing file or topic.
RecordedMotion recorded_motion(const std::filesystem::path& input, const std::string& odom,
                               const std::string& scan_topic);

}  // namespace fieldlidar::app
