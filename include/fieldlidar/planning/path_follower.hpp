#pragma once
/// \file Following a planned path: pure pursuit on each forward or reverse run of the path in
/// turn, with speed, acceleration, yaw-rate and curvature (1/R_min) limits, stopping at every
/// change of direction (cusp) and at the end. Map frame, m, s, rad.

#include <cstddef>
#include <vector>

#include "fieldlidar/planning/pose2.hpp"

namespace fieldlidar::planning {

struct FollowerConfig {
  double max_speed_m_s = 1.0;          ///< forward cruise speed
  double max_reverse_speed_m_s = 0.5;  ///< backwards
  double max_accel_m_s2 = 0.8;         ///< speeding up and braking
  double max_yaw_rate_rad_s = 1.0;
  double min_turn_radius_m = 1.0;  ///< the commanded curvature never exceeds 1 / R_min
  double lookahead_m = 0.6;        ///< pure-pursuit look-ahead along the path
  double min_speed_m_s = 0.1;      ///< creeping speed on the last centimetres before a stop
  /// A run's end is reached once the robot is this close to it (along its heading) or past it.
  double end_tolerance_m = 0.05;
};

/// One control period's command: forward speed (negative backwards) and yaw rate.
struct DriveCommand {
  double v_m_s = 0.0;
  double yaw_rate_rad_s = 0.0;
  bool done = false;           ///< the path's last run is finished: stand still
  std::size_t index = 0;       ///< the path sample the robot is at (progress)
  double cross_track_m = 0.0;  ///< distance to that sample
  double remaining_m = 0.0;    ///< path length still to drive
};

class PathFollower {
 public:
  explicit PathFollower(FollowerConfig config = {});

  /// A new path (the first sample at or near the robot); progress restarts at its beginning.
  void set_path(Path path);
  const Path& path() const { return path_; }
  bool has_path() const { return !path_.empty(); }
  void clear() { path_.clear(); }

  /// The command for the next `dt_s`, from the robot's pose and its current forward speed.
  DriveCommand command(const Pose2& pose, double v_now_m_s, double dt_s);

  std::size_t index() const { return index_; }
  const FollowerConfig& config() const { return config_; }

 private:
  struct Run {
    std::size_t begin = 0, end = 0;  ///< sample indices (end inclusive)
    bool reverse = false;
  };
  Pose2 lookahead_point(const Run& run, double s_m) const;

  FollowerConfig config_;
  Path path_;
  std::vector<double> s_m_;  ///< arc length at each sample
  std::vector<Run> runs_;
  std::size_t run_ = 0, index_ = 0;
};

/// Integrates a unicycle over dt_s (exact arcs): the pose after driving at v_m_s with the yaw
/// rate yaw_rate_rad_s.
Pose2 integrate_unicycle(const Pose2& pose, double v_m_s, double yaw_rate_rad_s, double dt_s);

}  // namespace fieldlidar::planning
