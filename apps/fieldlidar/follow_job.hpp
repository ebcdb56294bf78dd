#pragma once
// The `follow` job, shared by the follow command and the demo.

#include <cstdint>
#include <string>
#include <vector>

namespace fieldlidar::app {

struct FollowOptions {
  std::string scene = "lawn";
  std::string sensor = "vlp16";
  std::string scenario = "default";
  std::uint64_t seed = 0;
  std::string out;
  bool force = false;
  std::int64_t target_id = -1;
  double max_time_s = 0;
  double safe_distance_m = -1;
  double max_distance_m = -1;
  std::string origin;  ///< "LAT,LON[,HEADING_DEG]" for WGS84 GeoJSON; empty: local metres
  std::string pose_source = "odometry";  ///< odometry or truth
  // Replay of a recording instead of the simulation:
  std::string replay;       ///< ROS1 bag
  std::string topic;        ///< its scan topic ("" = the only one)
  std::string odom_topic;   ///< nav_msgs/Odometry topic: the robot's motion ("" = standing still)
  std::string legs_config;  ///< 2D leg detector YAML ("" = the shipped legs_2d.yaml)
  double rate_hz = 0;       ///< > 0: frames stamped at this rate from the first one's stamp
  /// The sensor's mount on the base, x y z (m) roll pitch yaw (deg); empty: the recording's /tf
  /// with --odom, else level by the first 3D sweep's ground (a 2D laser: as it stands).
  std::vector<double> mount;
};

/// Runs the follow pipeline on the recording `o.replay` and writes follow_log.csv, summary.json
/// and follow.png into `o.out`; prints a short summary.
void run_follow_replay(const FollowOptions& o);

/// Runs the simulated closed loop and writes boundary.geojson, boundary.csv, follow_log.csv,
/// summary.json and follow.png into `o.out`; prints a one-paragraph summary.
void run_follow(const FollowOptions& o);

}  // namespace fieldlidar::app
