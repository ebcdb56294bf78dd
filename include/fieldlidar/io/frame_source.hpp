#pragma once
/// \file One way to read LiDAR frames from every supported input: single cloud files, folders or
/// globs of them, Velodyne and Ouster packet captures, ROS1 bags.

#include <cstddef>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "fieldlidar/core/imu_sample.hpp"

#include "fieldlidar/core/point_cloud.hpp"
#include "fieldlidar/core/pose.hpp"
#include "fieldlidar/core/sensor_model.hpp"

namespace fieldlidar::io {

/// One full sweep (spinning sensor) or one scan message.
struct Frame {
  PointCloud cloud;       ///< sensor frame; ring and per-point time filled when the input has them
  double stamp_s = 0;     ///< s, same as cloud.stamp_s (capture, sensor or header clock)
  std::size_t index = 0;  ///< 0-based position in the stream
  std::string topic;      ///< bag topic, or the file the frame came from
  /// False for a sweep cut short by the start or end of a capture (or lost packets): it covers
  /// less than a full turn. Single files and bag messages are always complete.
  bool complete = true;
};

using fieldlidar::ImuSample;  // core/imu_sample.hpp

/// Wheel/visual odometry: pose of the child frame in the odometry frame, twist in the child frame.
struct OdometrySample {
  double stamp_s = 0;
  Pose pose = Pose::Identity();
  Eigen::Vector3d linear_m_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular_rad_s = Eigen::Vector3d::Zero();
  std::string child_frame_id;  ///< the frame whose pose this is (e.g. base_link), when known
};

struct PoseArraySample {
  double stamp_s = 0;
  std::string frame_id;
  std::vector<Pose> poses;
};

struct SourceOptions {
  std::string topic;               ///< bag topic of the frames; "" = the only cloud/scan topic
  std::filesystem::path metadata;  ///< Ouster metadata JSON; "" = <capture>.json beside it
};

/// A stream of frames, read lazily (a capture or bag is never loaded whole).
class FrameSource {
 public:
  /// Opens `input`: a .bin/.pcd/.ply/.las file, a folder of them (name order), a glob such as
  /// "scans/*.pcd", a Velodyne or Ouster .pcap, or a ROS1 .bag. A folder's frames are stamped by
  /// the KITTI-style times.txt in it or beside it (a KITTI sequence's velodyne/, a simulator
  /// folder's pcd/) when it lists one stamp per file. A folder without cloud files of its own
  /// that holds a pcd/ or else a velodyne/ folder of them (a simulator's output, a KITTI
  /// sequence) opens as that folder's frames. Throws fieldlidar::Error naming the input and the
  /// problem.
  static std::unique_ptr<FrameSource> open(const std::filesystem::path& input,
                                           const SourceOptions& options = {});
  virtual ~FrameSource();

  /// Next full sweep / scan message; nullopt at the end. Throws fieldlidar::Error on corrupt data.
  virtual std::optional<Frame> next() = 0;
  /// "kitti-bin", "pcd", "ply", "las", "velodyne-pcap", "ouster-pcap", "rosbag".
  virtual std::string format() const = 0;
  /// Sensor geometry when the input tells it (Velodyne model byte, Ouster metadata).
  virtual std::optional<SensorModel> sensor() const;
  /// IMU / odometry messages carried by the input with stamps up to and including `until_s`, in
  /// time order, each returned once.
  virtual std::vector<ImuSample> imu_until(double until_s);
  virtual std::vector<OdometrySample> odometry_until(double until_s);
  /// Fraction of the input consumed so far, in [0, 1] (for progress bars).
  virtual double progress() const { return 0.0; }
  /// What was lost without stopping the stream, so far (e.g. a capture cut inside a record, as
  /// when its recorder is killed: every sweep before the cut is read, the tail is not). Empty for
  /// a clean input; the caller reports these, the library never prints.
  virtual std::vector<std::string> warnings() const;
};

}  // namespace fieldlidar::io
