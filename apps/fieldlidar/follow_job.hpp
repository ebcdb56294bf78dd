#pragma once
// The `follow` job, shared by the follow command and the demo.

#include <cstdint>
#include <string>

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
};

/// Runs the simulated closed loop and writes boundary.geojson, boundary.csv, follow_log.csv,
/// summary.json and follow.png into `o.out`; prints a one-paragraph summary.
void run_follow(const FollowOptions& o);

}  // namespace fieldlidar::app
