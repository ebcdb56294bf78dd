#pragma once
/// \file Following the operator (seed 000, steps 6-7): the safety rule on the distance L, the
/// operator's trail (breadcrumbs of the estimated positions) and the differential-drive
/// controller choosing the wheel speed difference dv that minimises (k_p e_p)^2 + e_fai^2 over
/// the kinematic prediction. World frame x-y (m), yaw (rad, CCW from +x), speeds in m/s.

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "fieldlidar/core/pose2.hpp"

namespace fieldlidar::follow {

/// Planar pose of the mower (world frame): position of the sensor axis and heading.
using fieldlidar::Pose2;

enum class FollowState { kIdle, kFollowing, kTooClose, kTooFar, kLost };
std::string to_string(FollowState state);

/// Seed 000, step 6: the distances that allow following.
struct SafetyConfig {
  double safe_distance_m = 1.2;  ///< L_s: nearer than this, both wheels stop
  double max_distance_m = 7.0;   ///< L_m: farther than this, both wheels stop
};

/// Seed 000, step 6: L = sqrt(xc^2 + yc^2) with (xc, yc) the target in the mower frame; following
/// is allowed only when L_s < L < L_m and the target is tracked (not lost).
FollowState check_safety(const std::optional<Eigen::Vector2d>& target_in_mower_m,
                         const SafetyConfig& config);

/// The mower's drive (seed 000, step 7) and the controller's tuning.
struct DriveConfig {
  double track_width_m = 0.40;       ///< distance between the wheels; omega = dv / track_width
  double wheel_diameter_m = 0.20;    ///< D
  double gear_ratio = 30.0;          ///< k: motor revolutions per wheel revolution
  double max_speed_m_s = 1.4;        ///< forward speed limit
  double max_accel_m_s2 = 1.2;       ///< forward acceleration limit (not applied to safety stops)
  double max_wheel_speed_m_s = 1.6;  ///< |v_l|, |v_r| limit
  double max_dv_m_s = 0.6;           ///< |dv| limit (turn rate limit = max_dv / track_width)
  double max_dv_rate_m_s2 = 3.0;     ///< how fast dv may change
  double follow_distance_m = 2.2;    ///< desired distance to the operator
  double speed_gain_1_s = 0.8;       ///< v = gain * (L - follow_distance), clamped
  double lateral_weight = 2.0;       ///< k_p in (k_p e_p)^2 + e_fai^2 (1/m)
  double prediction_s = 0.6;         ///< horizon of the kinematic prediction
  int dv_samples = 81;               ///< dv candidates evaluated over [-max_dv, max_dv]
  double trail_spacing_m = 0.20;     ///< breadcrumbs at least this far apart (m)
};

/// Wheel speeds as commanded (seed 000, step 7): v_l = v - dv/2, v_r = v + dv/2 and the motor
/// speeds omega = v_wheel * k / (pi * D) (motor revolutions per second).
struct WheelCommand {
  double v_m_s = 0, dv_m_s = 0;
  double left_m_s = 0, right_m_s = 0;
  double left_motor_rev_s = 0, right_motor_rev_s = 0;
  bool moving() const { return left_m_s != 0.0 || right_m_s != 0.0; }
};
WheelCommand make_wheel_command(double v_m_s, double dv_m_s, const DriveConfig& drive);

/// The operator's trail: estimated operator positions (world) as breadcrumbs, with the mower's
/// progress along it so the mower passes where the operator walked and does not cut corners.
class Trail {
 public:
  explicit Trail(double spacing_m = 0.1) : spacing_m_(spacing_m) {}
  /// Adds a breadcrumb when it is at least `spacing_m` from the last one.
  void add(const Eigen::Vector2d& p_m);
  const std::vector<Eigen::Vector2d>& points() const { return points_; }
  bool empty() const { return points_.empty(); }
  /// Advances the mower's progress to the trail segment nearest to `p_m`, searching only forward
  /// from the current progress (a trail that crosses itself is not short-cut).
  void update_progress(const Eigen::Vector2d& p_m);
  std::size_t progress() const { return progress_; }

  struct Projection {
    double lateral_m = 0;    ///< signed distance, left of the trail positive
    double heading_rad = 0;  ///< direction of the trail there
    double along_m = 0;      ///< arc length from the progress point
    bool valid = false;
  };
  /// Nearest point of the trail ahead of the progress (within `window` segments) to `p_m`.
  Projection project(const Eigen::Vector2d& p_m, std::size_t window = 60) const;

 private:
  double spacing_m_;
  std::vector<Eigen::Vector2d> points_;
  std::size_t progress_ = 0;
};

/// Unicycle prediction of the mower pose after `dt_s` at forward speed v and wheel difference dv.
Pose2 predict_pose(const Pose2& pose, double v_m_s, double dv_m_s, double track_width_m,
                   double dt_s);

/// Seed 000, step 7: dv in [-max_dv, max_dv] minimising (k_p e_p)^2 + e_fai^2 of the predicted
/// pose against the trail (sampled, then refined on a parabola through the best three).
double choose_dv(const Pose2& pose, double v_m_s, const Trail& trail, const DriveConfig& drive);

/// State of the drive between frames: applies speed and acceleration limits, and the safety rule.
class FollowController {
 public:
  explicit FollowController(const DriveConfig& drive = {}, const SafetyConfig& safety = {});

  struct Output {
    WheelCommand command;
    FollowState state = FollowState::kIdle;
    double distance_m = -1;  ///< L (m), -1 when there is no target
  };
  /// One control period: `target_in_mower_m` is the tracked target in the mower frame (nullopt
  /// when lost); `trail` holds the operator's breadcrumbs in the world frame.
  Output step(const Pose2& mower, const std::optional<Eigen::Vector2d>& target_in_mower_m,
              Trail& trail, double dt_s);

  const DriveConfig& drive() const { return drive_; }
  const SafetyConfig& safety() const { return safety_; }

 private:
  DriveConfig drive_;
  SafetyConfig safety_;
  double v_ = 0, dv_ = 0;
};

}  // namespace fieldlidar::follow
