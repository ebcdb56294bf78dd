#pragma once
/// \file ROS1 bags: sensor_msgs/PointCloud2, LaserScan, Imu, nav_msgs/Odometry,
/// geometry_msgs/TwistStamped, geometry_msgs/PoseArray and leg_tracker/Person, decoded from their
/// serialized bytes (ROS1 wire format).

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
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

/// All sensor_msgs/Imu messages of `topic`, in bag order sorted by header stamp (the IMU's own
/// frame; orientation and covariances are not read). Throws fieldlidar::Error listing the bag's
/// topics when `topic` is absent or of another type.
std::vector<ImuSample> read_imu_topic(const std::filesystem::path& bag, const std::string& topic);
/// All nav_msgs/Odometry or geometry_msgs/TwistStamped messages of `topic`, sorted by header
/// stamp (TwistStamped: twist only, pose identity). Throws fieldlidar::Error listing the bag's
/// topics when `topic` is absent or of another type.
std::vector<OdometrySample> read_odometry_topic(const std::filesystem::path& bag,
                                                const std::string& topic);

/// One transform of tf2_msgs/TFMessage (geometry_msgs/TransformStamped).
struct TransformSample {
  double stamp_s = 0;
  std::string parent, child;  ///< header frame_id and child_frame_id, as recorded
  Pose T_parent_child = Pose::Identity();
};

/// The transform `parent` -> `child` (frame names compared without a leading '/') from the first
/// tf2_msgs/TFMessage of the bag's /tf_static or /tf topics that holds that edge (a fixed mount,
/// e.g. base_link -> laser); nullopt when none does. Only direct edges are looked up.
std::optional<Pose> read_mount_transform(const std::filesystem::path& bag,
                                         const std::string& parent, const std::string& child);
/// The header frame_id of the first message of `topic` (a message that starts with a
/// std_msgs/Header: scans, clouds, odometry, IMU). Throws fieldlidar::Error listing the bag's
/// topics when `topic` is absent or has no message.
std::string first_frame_id(const std::filesystem::path& bag, const std::string& topic);

/// leg_tracker/Person, the person annotation of the leg_tracker benchmarks: a pose and an id, no
/// header (no stamp, no frame).
struct PersonAnnotation {
  std::uint32_t id = 0;
  Pose pose = Pose::Identity();
};

/// The annotations that belong to one scan.
struct ScanAnnotations {
  double scan_stamp_s = 0;  ///< header stamp of the scan
  std::vector<PersonAnnotation> people;
};

/// leg_tracker/Person messages of `person_topic` paired with the scans of `scan_topic` by bag
/// order, as the leg_tracker benchmark scores them: the messages recorded after a scan and before
/// the next one belong to that scan (those before the first scan belong to none). One entry per
/// scan message, in the order a FrameSource on `scan_topic` yields the frames. Throws
/// fieldlidar::Error naming the bag's topics when a topic is absent or of another type.
std::vector<ScanAnnotations> read_person_annotations(const std::filesystem::path& bag,
                                                     const std::string& scan_topic,
                                                     const std::string& person_topic);

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
/// geometry_msgs/TwistStamped -> an odometry sample with the twist only (pose identity).
OdometrySample parse_twist_stamped(std::span<const std::uint8_t> bytes);
PoseArraySample parse_pose_array(std::span<const std::uint8_t> bytes);
std::vector<TransformSample> parse_tf_message(std::span<const std::uint8_t> bytes);
PersonAnnotation parse_leg_tracker_person(std::span<const std::uint8_t> bytes);

}  // namespace fieldlidar::io
