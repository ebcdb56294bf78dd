// ROS1 bags: whole topics of one message type (PoseArray, Imu, Odometry/TwistStamped), the
// sensor mounts of tf2_msgs/TFMessage and a topic's header frame.
#include <cstring>
#include <initializer_list>
#include <limits>
#include <optional>

#include "fieldlidar/io/rosbag_reader.hpp"
#include "rosbag_common.hpp"

namespace fieldlidar::io {

using namespace rosbag_detail;

namespace {

/// The topic `name` of `bag`, checked to be one of `types` (md5 included); its index in `types`.
std::size_t typed_topic(const std::filesystem::path& path, rosbag::Bag& bag,
                        const std::string& name, std::initializer_list<KnownType> types) {
  const auto topics = topics_of(bag);
  auto it =
      std::find_if(topics.begin(), topics.end(), [&](const BagTopic& t) { return t.name == name; });
  if (it == topics.end())
    throw Error(path.string() + ": no topic '" + name +
                "' in the bag; topics: " + list_topics(topics));
  std::string expected;
  std::size_t k = 0;
  for (const auto& type : types) {
    if (is_type(*it, type)) {
      check_md5(path, *it, type);
      return k;
    }
    expected += std::string(k++ ? " or " : "") + type.datatype;
  }
  throw Error(path.string() + ": topic '" + name + "' is " + it->datatype + ", not " + expected +
              "; topics: " + list_topics(topics));
}

template <class Sample>
std::vector<Sample> read_all(const std::filesystem::path& path, const CheckedBag& bag,
                             const std::string& topic,
                             Sample (*parse)(std::span<const std::uint8_t>)) {
  try {
    TopicStream<Sample> stream(bag, {topic}, parse, path.string());
    return stream.until(std::numeric_limits<double>::infinity());
  } catch (const rosbag::BagException& e) {
    throw Error(path.string() + ": " + e.what());
  }
}

}  // namespace

std::vector<PoseArraySample> read_pose_arrays(const std::filesystem::path& bag,
                                              const std::string& topic) {
  auto b = open_bag(bag);
  typed_topic(bag, *b, topic, {kPoseArray});
  return read_all(bag, *b, topic, &parse_pose_array);
}

std::vector<ImuSample> read_imu_topic(const std::filesystem::path& bag, const std::string& topic) {
  auto b = open_bag(bag);
  typed_topic(bag, *b, topic, {kImu});
  return read_all(bag, *b, topic, &parse_imu);
}

std::vector<OdometrySample> read_odometry_topic(const std::filesystem::path& bag,
                                                const std::string& topic) {
  auto b = open_bag(bag);
  const bool twist = typed_topic(bag, *b, topic, {kOdometry, kTwistStamped}) == 1;
  return read_all(bag, *b, topic, twist ? &parse_twist_stamped : &parse_odometry);
}

std::optional<Pose> read_mount_transform(const std::filesystem::path& path,
                                         const std::string& parent, const std::string& child) {
  auto bag = open_bag(path);
  auto bare = [](const std::string& f) { return f.rfind('/', 0) == 0 ? f.substr(1) : f; };
  const std::string p = bare(parent), c = bare(child);
  std::vector<std::uint8_t> buf;
  try {
    for (const auto& t : topics_of(*bag)) {
      if (!is_type(t, kTfMessage) || (t.name != "/tf_static" && t.name != "/tf")) continue;
      check_md5(path, t, kTfMessage);
      for (const auto& m : rosbag::View(*bag, rosbag::TopicQuery(t.name))) {
        message_bytes(*bag, m, buf);
        for (const auto& tf : parse_tf_message(buf))
          if (bare(tf.parent) == p && bare(tf.child) == c) return tf.T_parent_child;
      }
    }
  } catch (const rosbag::BagException& e) {
    throw Error(path.string() + ": a message cannot be read: " + e.what());
  } catch (const Error& e) {
    throw Error(path.string() + ": " + e.what());
  }
  return std::nullopt;
}

std::string first_frame_id(const std::filesystem::path& path, const std::string& topic) {
  auto bag = open_bag(path);
  const auto topics = topics_of(*bag);
  try {
    rosbag::View view(*bag, rosbag::TopicQuery(topic));
    if (view.size() == 0)
      throw Error(path.string() + ": no message on topic '" + topic +
                  "'; topics: " + list_topics(topics));
    std::vector<std::uint8_t> buf;
    message_bytes(*bag, *view.begin(), buf);
    // std_msgs/Header: seq, stamp sec, stamp nsec, frame_id (uint32 length + chars).
    std::uint32_t n = 0;
    if (buf.size() >= 16) std::memcpy(&n, buf.data() + 12, 4);
    if (buf.size() < 16 || n > buf.size() - 16)
      throw Error(path.string() + ": topic '" + topic + "': the first message has no header");
    return std::string(reinterpret_cast<const char*>(buf.data() + 16), n);
  } catch (const rosbag::BagException& e) {
    throw Error(path.string() + ": " + e.what());
  }
}

}  // namespace fieldlidar::io
