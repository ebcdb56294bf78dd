#pragma once
/// \file ROS1 bags: sensor_msgs/PointCloud2, LaserScan, Imu, nav_msgs/Odometry and
/// geometry_msgs/PoseArray, decoded from their serialized bytes (ROS1 wire format).

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "fieldlidar/io/frame_source.hpp"

namespace fieldlidar::io {

/// One connection topic of a bag.
struct BagTopic {
  std::string name;
  std::string datatype;  ///< e.g. "sensor_msgs/LaserScan"
  std::string md5sum;
  std::size_t messages = 0;
};

/// Topics of a bag with their types and message counts (reads only the index).
std::vector<BagTopic> bag_topics(const std::filesystem::path& bag);
/// Message count per topic.
std::map<std::string, std::size_t> bag_topic_counts(const std::filesystem::path& bag);
/// All geometry_msgs/PoseArray messages of `topic` (stamp_s = header stamp); throws
/// fieldlidar::Error listing the bag's topics when `topic` is absent or of another type.
std::vector<PoseArraySample> read_pose_arrays(const std::filesystem::path& bag,
                                              const std::string& topic);

/// A bag as a FrameSource: frames from one PointCloud2 or LaserScan topic, IMU and odometry from
/// every sensor_msgs/Imu and nav_msgs/Odometry topic.
std::unique_ptr<FrameSource> open_rosbag(const std::filesystem::path& bag,
                                         const std::string& topic);

// Message decoders (exposed for tests and fuzzing). Each throws fieldlidar::Error when the bytes
// are shorter than the message or a field is inconsistent.

/// sensor_msgs/LaserScan -> one-ring cloud: ring 0, points in scan-angle order, beams outside
/// [range_min, range_max] or not finite skipped, time = offset of the beam within the scan,
/// stamp_s = header stamp.
PointCloud parse_laser_scan(std::span<const std::uint8_t> bytes);
/// sensor_msgs/PointCloud2 with float32/float64 x y z and optional intensity, ring, time or t
/// (any numeric type); NaN points dropped; organized layout kept when the cloud is dense.
PointCloud parse_point_cloud2(std::span<const std::uint8_t> bytes);
ImuSample parse_imu(std::span<const std::uint8_t> bytes);
OdometrySample parse_odometry(std::span<const std::uint8_t> bytes);
PoseArraySample parse_pose_array(std::span<const std::uint8_t> bytes);

}  // namespace fieldlidar::io
