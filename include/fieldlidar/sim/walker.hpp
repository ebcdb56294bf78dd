#pragma once
/// \file A walking person: a path, a speed schedule and a gait (two swinging legs, torso, head),
/// evaluated at any time so that the sensor sees the person where they are at each firing.

#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace fieldlidar::sim {

/// A capsule: the points within `radius_m` of the segment a-b (world frame, m). a == b is a sphere.
struct Capsule {
  Eigen::Vector3d a = Eigen::Vector3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  double radius_m = 0.0;
};

/// The body of a person at one instant: legs[0], legs[1], torso, head.
struct PersonBody {
  std::uint16_t id = 0;
  std::array<Capsule, 4> parts;
  Eigen::Vector3d bound_center_m = Eigen::Vector3d::Zero();  ///< sphere enclosing all parts
  double bound_radius_m = 0.0;
};

/// From `t_start_s` on, the person walks at `speed_m_s` (0 = standing) until the next phase.
struct SpeedPhase {
  double t_start_s = 0.0;
  double speed_m_s = 1.0;
};

struct WalkerConfig {
  std::uint16_t id = 1;                          ///< person id, the label instance of their points
  std::vector<Eigen::Vector2d> path_m;           ///< world x-y polyline (>= 2 points)
  bool closed = false;                           ///< walk around the polygon forever
  double start_offset_m = 0.0;                   ///< arc length along the path at t = 0
  std::vector<SpeedPhase> speed = {{0.0, 1.0}};  ///< ascending t_start_s; the first applies before
  double height_m = 1.75;                        ///< standing height (scales legs and torso)
  double stride_m = 1.3;                         ///< one full gait cycle (two steps) along the path
  double leg_radius_m = 0.065;
  double torso_radius_m = 0.16;
  double hip_width_m = 0.2;  ///< lateral distance between the two legs' axes
};

/// Truth of one person: where they are (m, world), velocity (m/s), the two legs' axes at knee
/// height (0.45 m above the ground) — what a LiDAR at mower height sees.
struct PersonTruth {
  std::uint16_t id = 0;
  Eigen::Vector2d position_m = Eigen::Vector2d::Zero();
  Eigen::Vector2d velocity_m_s = Eigen::Vector2d::Zero();
  std::array<Eigen::Vector2d, 2> legs_m{Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero()};
  /// True in Scene::people_at (the scene knows no sensor); in a SimFrame false, and `points`
  /// says how many returns of the sweep hit the person.
  bool visible_from_sensor_unknown = true;
  std::uint32_t points = 0;    ///< returns on this person in a SimFrame
  double heading_rad = 0.0;    ///< walking direction (yaw of the path)
  double path_length_m = 0.0;  ///< unwrapped arc length walked along the path
};

/// A person following a polyline with a piecewise-constant speed.
class Walker {
 public:
  explicit Walker(WalkerConfig config);

  const WalkerConfig& config() const { return config_; }
  std::uint16_t id() const { return config_.id; }
  /// Unwrapped arc length (m) walked at time t (s); constant while the speed is 0.
  double arc_length_at(double t_s) const;
  double speed_at(double t_s) const;
  /// Point and unit direction of the path at unwrapped arc length s (wraps when closed, clamps
  /// otherwise).
  void path_point(double s_m, Eigen::Vector2d& xy_m, Eigen::Vector2d& dir) const;
  double path_length_m() const { return cumulative_.back(); }

  /// Truth and body at time t; `ground_z_m` is the ground height under the person.
  PersonTruth truth_at(double t_s) const;
  PersonBody body_at(double t_s, double ground_z_m) const;

 private:
  /// Gait: fore-aft offset (m) of leg k's foot from the hip line, from the gait phase.
  double foot_offset(int leg, double t_s) const;

  WalkerConfig config_;
  std::vector<double> cumulative_;  ///< arc length at each vertex (closing edge included)
};

}  // namespace fieldlidar::sim
