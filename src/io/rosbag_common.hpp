#pragma once
// Shared by the ROS1 bag readers (rosbag_reader.cpp, rosbag_topics.cpp): the message types this
// library decodes, opening a bag, its topics, and a lazy time-ordered stream of one message type.

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <ros/serialization.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/rosbag_reader.hpp"

namespace fieldlidar::io::rosbag_detail {

// md5 sums of the ROS1 message definitions this reader decodes (from the connection header; a
// different sum means a different layout, which must not be decoded with these parsers).
struct KnownType {
  const char* datatype;
  const char* md5;
};
constexpr KnownType kLaserScan{"sensor_msgs/LaserScan", "90c7ef2dc6895d81024acba2ac42f369"};
constexpr KnownType kPointCloud2{"sensor_msgs/PointCloud2", "1158d486dd51d683ce2f1be655c3c181"};
constexpr KnownType kImu{"sensor_msgs/Imu", "6a62c6daae103f4ff57a132d6f95cec2"};
constexpr KnownType kOdometry{"nav_msgs/Odometry", "cd5e73d190d741a2f92e81eda573aca7"};
constexpr KnownType kTwistStamped{"geometry_msgs/TwistStamped", "98d34b0043a2093cf9d9345ab6eef12e"};
constexpr KnownType kTfMessage{"tf2_msgs/TFMessage", "94810edda583a504dfda3829e70d7eec"};
constexpr KnownType kPoseArray{"geometry_msgs/PoseArray", "916c28c5764443f268b296bb671b9d97"};
constexpr KnownType kPerson{"leg_tracker/Person", "4f334171b5664340c323a1982b554a22"};

inline bool is_type(const BagTopic& t, const KnownType& k) {
  return t.datatype == k.datatype;
}

inline void check_md5(const std::filesystem::path& bag, const BagTopic& t, const KnownType& k) {
  if (t.md5sum != k.md5 && t.md5sum != "*")
    throw Error(bag.string() + ": topic '" + t.name + "' has type " + t.datatype + " with md5 " +
                t.md5sum + ", expected " + k.md5 + " (a different message definition)");
}

inline std::string list_topics(const std::vector<BagTopic>& topics) {
  std::string s;
  for (const auto& t : topics)
    s += (s.empty() ? "" : ", ") + t.name + " [" + t.datatype + ", " + std::to_string(t.messages) +
         "]";
  return s.empty() ? "(none)" : s;
}

/// The largest uncompressed chunk of the bag at `path` (bytes; rosbag_chunks.cpp): no message is
/// longer. The file's size for a version 1.2 bag; 0 when its index cannot be read.
std::uint64_t bag_max_chunk_bytes(const std::filesystem::path& path);

/// A bag open for reading, with the bound its messages' lengths are checked against.
class CheckedBag : public rosbag::Bag {
 public:
  std::uint64_t max_message_bytes = 0;
};

inline std::unique_ptr<CheckedBag> open_bag(const std::filesystem::path& path) {
  if (!std::filesystem::exists(path)) throw Error(path.string() + ": no such file");
  auto bag = std::make_unique<CheckedBag>();
  try {
    bag->open(path.string(), rosbag::bagmode::Read);
  } catch (const std::exception& e) {
    throw Error(path.string() + ": not a readable ROS1 bag (" + e.what() + ")");
  }
  bag->max_message_bytes = bag_max_chunk_bytes(path);
  return bag;
}

inline std::vector<BagTopic> topics_of(rosbag::Bag& bag) {
  std::vector<BagTopic> out;
  rosbag::View all(bag);
  for (const rosbag::ConnectionInfo* c : all.getConnections()) {
    auto it =
        std::find_if(out.begin(), out.end(), [&](const BagTopic& t) { return t.name == c->topic; });
    if (it != out.end()) continue;
    BagTopic t;
    t.name = c->topic;
    t.datatype = c->datatype;
    t.md5sum = c->md5sum;
    out.push_back(t);
  }
  for (auto& t : out) t.messages = rosbag::View(bag, rosbag::TopicQuery(t.name)).size();
  std::sort(out.begin(), out.end(),
            [](const BagTopic& a, const BagTopic& b) { return a.name < b.name; });
  return out;
}

/// The serialized bytes of `m` from `bag`; a length beyond the bag's largest chunk (a damaged
/// record) is a rosbag::BagFormatException, which the readers report with the topic and message.
inline void message_bytes(const CheckedBag& bag, const rosbag::MessageInstance& m,
                          std::vector<std::uint8_t>& buf) {
  const std::uint32_t n = m.size();
  if (n > bag.max_message_bytes)
    throw rosbag::BagFormatException("its record claims " + std::to_string(n) +
                                     " bytes, more than the bag's largest chunk holds (" +
                                     std::to_string(bag.max_message_bytes) +
                                     "): the bag is damaged");
  buf.resize(n);
  ros::serialization::OStream s(buf.data(), std::uint32_t(buf.size()));
  m.write(s);
}

/// Lazily walks the messages of some topics in bag-time order, with one message of look-ahead.
template <class Sample>
class TopicStream {
 public:
  using Parser = Sample (*)(std::span<const std::uint8_t>);
  TopicStream(const CheckedBag& bag, const std::vector<std::string>& topics, Parser parse,
              std::string source)
      : bag_(&bag), parse_(parse), source_(std::move(source)) {
    if (topics.empty()) return;
    view_ = std::make_unique<rosbag::View>(bag, rosbag::TopicQuery(topics));
    it_ = view_->begin();
  }
  std::vector<Sample> until(double until_s) {
    std::vector<Sample> out;
    if (!view_) return out;
    for (;;) {
      if (!pending_) {
        std::string topic;
        try {
          if (it_ == view_->end()) break;
          message_bytes(*bag_, *it_, buf_);
          topic = it_->getTopic();
          ++it_;
        } catch (const rosbag::BagException& e) {
          throw Error(source_ + ": a message cannot be read: " + e.what());
        }
        try {
          pending_ = parse_(buf_);
        } catch (const Error& e) {
          throw Error(source_ + ": topic '" + topic + "': " + e.what());
        }
      }
      if (pending_->stamp_s > until_s) break;
      out.push_back(std::move(*pending_));
      pending_.reset();
    }
    std::stable_sort(out.begin(), out.end(),
                     [](const Sample& a, const Sample& b) { return a.stamp_s < b.stamp_s; });
    return out;
  }

 private:
  const CheckedBag* bag_;
  Parser parse_;
  std::string source_;
  std::unique_ptr<rosbag::View> view_;
  rosbag::View::iterator it_;
  std::optional<Sample> pending_;
  std::vector<std::uint8_t> buf_;
};

}  // namespace fieldlidar::io::rosbag_detail
