// ROS1 bags through rosbag_storage: the frame source, topic listing and person annotations;
// messages decoded from their serialized bytes.
#include "fieldlidar/io/rosbag_reader.hpp"

#include <algorithm>
#include <cstring>
#include <optional>

#include "rosbag_common.hpp"

namespace fieldlidar::io {
namespace {

using namespace rosbag_detail;

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
      message_bytes(*bag_, *it_, buf_);
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
  std::unique_ptr<CheckedBag> bag_;
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
      message_bytes(*b, m, buf);
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

std::unique_ptr<FrameSource> open_rosbag(const std::filesystem::path& bag,
                                         const std::string& topic) {
  try {
    return std::make_unique<RosbagSource>(bag, topic);
  } catch (const rosbag::BagException& e) {
    throw Error(bag.string() + ": " + e.what());
  }
}

}  // namespace fieldlidar::io
