// The navigate loop's approach: the sweeps the robot took while driving to its start, fused into
// the map before the first sweep at the start (NavigateConfig::approach_m).

#include <cmath>

#include "navigate_loop.hpp"

namespace fieldlidar::loops::detail {

std::size_t Loop::approach() {
  if (!(cfg_.approach_m > 0)) return 0;
  // The approach's poses from the start backwards, as far as the robot could have driven.
  const double step = cfg_.approach_sweep_m;
  const int n = int(std::floor(cfg_.approach_m / step + 1e-9));
  const double c = std::cos(pose_.yaw_rad), s = std::sin(pose_.yaw_rad);
  std::vector<Pose2> poses;
  for (int k = 1; k <= n; ++k) {
    const Pose2 p{pose_.x_m - k * step * c, pose_.y_m - k * step * s, pose_.yaw_rad};
    if (on_truth_impassable(p)) break;
    poses.push_back(p);
  }
  // Swept in driving order, the farthest first, at the times they were taken (the last one a
  // sweep period before the start's first sweep).
  const double speed = cfg_.follower.max_speed_m_s;
  for (std::size_t k = poses.size(); k-- > 0;) {
    const double t = -double(k + 1) * step / speed;
    const Pose T = poses_->lidar_pose(poses[k]);
    const sim::SimFrame frame = lidar_.scan(t, T);
    map_sweep(frame.cloud, T);
    approach_sensors_.push_back(T.translation());
  }
  r_.approach_sweeps = poses.size();
  return poses.size();
}

}  // namespace fieldlidar::loops::detail
