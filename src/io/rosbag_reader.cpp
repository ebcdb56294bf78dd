// ROS1 bags through rosbag_storage; messages decoded from their serialized bytes.
#include "fieldlidar/io/rosbag_reader.hpp"

#include <algorithm>
#include <cstring>
#include <deque>
#include <limits>
#include <optional>

#include <ros/serialization.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>

#include "fieldlidar/core/error.hpp"

namespace fieldlidar::io {
namespace {

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

bool is_type(const BagTopic& t, const KnownType& k) {
  return t.datatype == k.datatype;
}

void check_md5(const std::filesystem::path& bag, const BagTopic& t, const KnownType& k) {
  if (t.md5sum != k.md5 && t.md5sum != "*")
    throw Error(bag.string() + ": topic '" + t.name + "' has type " + t.datatype + " with md5 " +
                t.md5sum + ", expected " + k.md5 + " (a different message definition)");
}

std::string list_topics(const std::vector<BagTopic>& topics) {
  std::string s;
  for (const auto& t : topics)
    s += (s.empty() ? "" : ", ") + t.name + " [" + t.datatype + ", " + std::to_string(t.messages) +
         "]";
  return s.empty() ? "(none)" : s;
}

std::unique_ptr<rosbag::Bag> open_bag(const std::filesystem::path& path) {
  if (!std::filesystem::exists(path)) throw Error(path.string() + ": no such file");
  auto bag = std::make_unique<rosbag::Bag>();
  try {
    bag->open(path.string(), rosbag::bagmode::Read);
  } catch (const std::exception& e) {
    throw Error(path.string() + ": not a readable ROS1 bag (" + e.what() + ")");
  }
  return bag;
}

std::vector<BagTopic> topics_of(rosbag::Bag& bag) {
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

void message_bytes(const rosbag::MessageInstance& m, std::vector<std::uint8_t>& buf) {
  buf.resize(m.size());
  ros::serialization::OStream s(buf.data(), std::uint32_t(buf.size()));
  m.write(s);
}

/// Lazily walks the messages of some topics in bag-time order, with one message of look-ahead.
template <class Sample>
class TopicStream {
 public:
  using Parser = Sample (*)(std::span<const std::uint8_t>);
  TopicStream(rosbag::Bag& bag, const std::vector<std::string>& topics, Parser parse,
              std::string source)
      : parse_(parse), source_(std::move(source)) {
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
          message_bytes(*it_, buf_);
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
  Parser parse_;
  std::string source_;
  std::unique_ptr<rosbag::View> view_;
  rosbag::View::iterator it_;
  std::optional<Sample> pending_;
  std::vector<std::uint8_t> buf_;
};

class RosbagSource final : public FrameSource {
 public:
  RosbagSource(const std::filesystem::path& path, const std::string& topic)
      : path_(path), bag_(open_bag(path)) {
    const auto topics = topics_of(*bag_);
    std::vector<const BagTopic*> scans;
    for (const auto& t : topics)
      if (is_type(t, kLaserScan) || is_type(t, kPointCloud2)) scans.push_back(&t);
    const BagTopic* chosen = nullptr;
    if (!topic.empty()) {
      for (const auto& t : topics)
        if (t.name == topic) chosen = &t;
      if (!chosen)
        throw Error(path.string() + ": no topic '" + topic +
                    "' in the bag; topics: " + list_topics(topics));
      if (!is_type(*chosen, kLaserScan) && !is_type(*chosen, kPointCloud2))
        throw Error(path.string() + ": topic '" + topic + "' is " + chosen->datatype +
                    ", not sensor_msgs/PointCloud2 or sensor_msgs/LaserScan; topics: " +
                    list_topics(topics));
    } else if (scans.size() == 1) {
      chosen = scans.front();
    } else if (scans.empty()) {
      throw Error(path.string() + ": no sensor_msgs/PointCloud2 or LaserScan topic; topics: " +
                  list_topics(topics));
    } else {
      throw Error(path.string() +
                  ": several scan topics, choose one with --topic; topics: " + list_topics(topics));
    }
    topic_ = *chosen;
    laser_scan_ = is_type(topic_, kLaserScan);
    check_md5(path, topic_, laser_scan_ ? kLaserScan : kPointCloud2);
    std::vector<std::string> imu_topics, odom_topics;
    for (const auto& t : topics) {
      if (is_type(t, kImu)) check_md5(path, t, kImu), imu_topics.push_back(t.name);
      if (is_type(t, kOdometry)) check_md5(path, t, kOdometry), odom_topics.push_back(t.name);
    }
    view_ = std::make_unique<rosbag::View>(*bag_, rosbag::TopicQuery(topic_.name));
    total_ = view_->size();
    it_ = view_->begin();
    imu_.emplace(*bag_, imu_topics, &parse_imu, path.string());
    odom_.emplace(*bag_, odom_topics, &parse_odometry, path.string());
  }

  std::optional<Frame> next() override {
    try {
      if (it_ == view_->end()) return std::nullopt;
      message_bytes(*it_, buf_);
      ++it_;
    } catch (const rosbag::BagException& e) {
      throw Error(path_.string() + ": topic '" + topic_.name + "' message " +
                  std::to_string(index_) + " cannot be read: " + e.what());
    }
    Frame f;
    try {
      f.cloud = laser_scan_ ? parse_laser_scan(buf_) : parse_point_cloud2(buf_);
    } catch (const Error& e) {
      throw Error(path_.string() + ": topic '" + topic_.name + "' message " +
                  std::to_string(index_) + ": " + e.what());
    }
    f.stamp_s = f.cloud.stamp_s;
    f.index = index_++;
    f.topic = topic_.name;
    return f;
  }
  std::string format() const override { return "rosbag"; }
  std::vector<ImuSample> imu_until(double until_s) override { return imu_->until(until_s); }
  std::vector<OdometrySample> odometry_until(double until_s) override {
    return odom_->until(until_s);
  }
  double progress() const override { return total_ ? double(index_) / double(total_) : 1.0; }

 private:
  std::filesystem::path path_;
  std::unique_ptr<rosbag::Bag> bag_;
  BagTopic topic_;
  bool laser_scan_ = false;
  std::unique_ptr<rosbag::View> view_;
  rosbag::View::iterator it_;
  std::size_t index_ = 0, total_ = 0;
  std::vector<std::uint8_t> buf_;
  std::optional<TopicStream<ImuSample>> imu_;
  std::optional<TopicStream<OdometrySample>> odom_;
};

}  // namespace

std::vector<BagTopic> bag_topics(const std::filesystem::path& bag) {
  auto b = open_bag(bag);
  try {
    return topics_of(*b);
  } catch (const rosbag::BagException& e) {
    throw Error(bag.string() + ": " + e.what());
  }
}

std::map<std::string, std::size_t> bag_topic_counts(const std::filesystem::path& bag) {
  std::map<std::string, std::size_t> out;
  for (const auto& t : bag_topics(bag)) out[t.name] = t.messages;
  return out;
}

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
std::vector<Sample> read_all(const std::filesystem::path& path, rosbag::Bag& bag,
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

std::vector<ScanAnnotations> read_person_annotations(const std::filesystem::path& bag,
                                                     const std::string& scan_topic,
                                                     const std::string& person_topic) {
  auto b = open_bag(bag);
  const auto topics = topics_of(*b);
  auto find = [&](const std::string& name) {
    auto it = std::find_if(topics.begin(), topics.end(),
                           [&](const BagTopic& t) { return t.name == name; });
    if (it == topics.end())
      throw Error(bag.string() + ": no topic '" + name +
                  "' in the bag; topics: " + list_topics(topics));
    return *it;
  };
  const BagTopic scans = find(scan_topic), people = find(person_topic);
  if (!is_type(scans, kLaserScan) && !is_type(scans, kPointCloud2))
    throw Error(bag.string() + ": topic '" + scan_topic + "' is " + scans.datatype +
                ", not sensor_msgs/LaserScan or sensor_msgs/PointCloud2");
  if (!is_type(people, kPerson))
    throw Error(bag.string() + ": topic '" + person_topic + "' is " + people.datatype +
                ", not leg_tracker/Person");
  check_md5(bag, people, kPerson);
  std::vector<ScanAnnotations> out;
  std::vector<std::uint8_t> buf;
  try {
    rosbag::View view(*b, rosbag::TopicQuery(std::vector<std::string>{scan_topic, person_topic}));
    for (const auto& m : view) {
      message_bytes(m, buf);
      if (m.getTopic() == scan_topic) {
        // Every scan message starts with a std_msgs/Header: seq, stamp sec, stamp nsec.
        if (buf.size() < 12)
          throw Error(bag.string() + ": topic '" + scan_topic + "' message " +
                      std::to_string(out.size()) + " is shorter than its header");
        std::uint32_t sec = 0, nsec = 0;
        std::memcpy(&sec, buf.data() + 4, 4);
        std::memcpy(&nsec, buf.data() + 8, 4);
        out.push_back({double(sec) + double(nsec) * 1e-9, {}});
      } else if (!out.empty()) {
        try {
          out.back().people.push_back(parse_leg_tracker_person(buf));
        } catch (const Error& e) {
          throw Error(bag.string() + ": topic '" + person_topic + "': " + e.what());
        }
      }
    }
  } catch (const rosbag::BagException& e) {
    throw Error(bag.string() + ": a message cannot be read: " + e.what());
  }
  return out;
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
        message_bytes(m, buf);
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
    message_bytes(*view.begin(), buf);
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

std::unique_ptr<FrameSource> open_rosbag(const std::filesystem::path& bag,
                                         const std::string& topic) {
  try {
    return std::make_unique<RosbagSource>(bag, topic);
  } catch (const rosbag::BagException& e) {
    throw Error(bag.string() + ": " + e.what());
  }
}

}  // namespace fieldlidar::io
