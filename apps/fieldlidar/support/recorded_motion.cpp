#include "support/recorded_motion.hpp"

#include <fmt/core.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/rosbag_reader.hpp"
#include "fieldlidar/io/trajectory_io.hpp"
#include "support/warnings.hpp"

namespace fieldlidar::app {

namespace fs = std::filesystem;

namespace {

/// The recorded odometry as a trajectory (samples with a repeated stamp dropped); `child_frame`
/// is set to the frame it tracks (the base).
Trajectory odometry_trajectory(const fs::path& bag, const std::string& topic,
                               std::string& child_frame) {
  Trajectory t;
  for (const auto& s : io::read_odometry_topic(bag, topic)) {
    if (child_frame.empty()) child_frame = s.child_frame_id;
    if (t.empty() || s.stamp_s > t.poses().back().stamp_s) t.push_back(s.stamp_s, s.pose);
  }
  if (t.size() < 2)
    throw Error(bag.string() + ": topic '" + topic + "' holds fewer than 2 odometry poses");
  return t;
}

/// The scan topic: `topic`, else the bag's only scan topic (as the frame source chooses it).
std::string scan_topic_of(const fs::path& bag, const std::string& topic) {
  if (!topic.empty()) return topic;
  for (const auto& t : io::bag_topics(bag))
    if (t.datatype == "sensor_msgs/LaserScan" || t.datatype == "sensor_msgs/PointCloud2")
      return t.name;
  return {};
}

}  // namespace

Pose RecordedMotion::base_at(double stamp_s) {
  if (auto p = poses.at(stamp_s)) return *p;
  const auto& first = poses.poses().front();
  const auto& last = poses.poses().back();
  if (stamp_s < first.stamp_s - kSpanSlackS || stamp_s > last.stamp_s + kSpanSlackS)
    ++frames_outside;
  return stamp_s < first.stamp_s ? first.pose : last.pose;
}

void RecordedMotion::warn_outside(const std::string& odom) const {
  if (frames_outside == 0) return;
  warn(fmt::format(
      "{} frames lie outside the time span of --odom {} ({:.3f} .. {:.3f} s): they "
      "were placed at its nearest end, as if the robot stood there",
      frames_outside, odom, poses.poses().front().stamp_s, poses.poses().back().stamp_s));
}

RecordedMotion recorded_motion(const fs::path& input, const std::string& odom,
                               const std::string& scan_topic) {
  RecordedMotion m;
  if (input.extension() != ".bag") {
    // Beside a simulator folder or a capture, --odom can only be a TUM pose file: a missing one
    // is named, not read as a bag topic.
    if (!fs::is_regular_file(odom))
      throw Error("--odom " + odom + ": no such file (with an input that is not a bag, --odom is " +
                  "a TUM pose file)");
    m.poses = io::read_tum(odom);
    if (m.poses.empty()) throw Error(odom + ": holds no pose");
    return m;
  }
  std::string base_frame;
  m.poses = odometry_trajectory(input, odom, base_frame);
  const std::string sensor_frame = io::first_frame_id(input, scan_topic_of(input, scan_topic));
  if (const auto T = io::read_mount_transform(input, base_frame, sensor_frame)) {
    m.T_base_sensor = *T;
    m.mount_from = "/tf: " + base_frame + " -> " + sensor_frame;
  } else {
    warn(
        fmt::format("no transform {} -> {} in the bag: the scans are taken as seen from the "
                    "base's origin and heading",
                    base_frame, sensor_frame));
  }
  return m;
}

}  // namespace fieldlidar::app
