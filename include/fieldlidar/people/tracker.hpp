#pragma once
/// \file Multi-person tracking (seed 000, step 5): one constant-velocity Kalman filter per
/// person, gated Mahalanobis data association solved as an assignment, track birth, confirmation
/// and deletion, stable ids, and a target chosen by id (seed 000, step 4).
///
/// The tracker works in one fixed frame (the world/odometry frame of the robot): detections must
/// be transformed into it before update(). Positions in m, velocities in m/s, times in s.

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <Eigen/Core>

namespace fieldlidar::people {

struct TrackerConfig {
  double accel_sigma_m_s2 = 1.5;      ///< white-noise acceleration driving Q
  double measurement_sigma_m = 0.08;  ///< sqrt of the diagonal of R
  double initial_speed_sigma_m_s = 1.0;
  double gate_chi2 = 9.21;             ///< Mahalanobis^2 gate (chi-square, 2 dof, 99 %)
  double gate_max_m = 1.2;             ///< and never farther than this from the prediction (m)
  int confirm_hits = 3;                ///< hits needed before a track is confirmed
  double tentative_max_miss_s = 0.25;  ///< a tentative track dies after missing this long
  double delete_after_miss_s = 3.0;    ///< a confirmed track dies after missing this long
  double max_speed_m_s = 3.0;          ///< speed estimates are clamped to this (people walk)
  /// No track is born this close to an existing track (m): two people do not overlap, so such a
  /// detection is a duplicate (e.g. a leg paired with the wrong leg).
  double birth_min_separation_m = 0.4;
  int coast_frames = 1;  ///< the target counts as lost after more missed frames than this
  /// While the target is lost, a confirmed track born after the target's last detection within
  /// reacquire_radius_m + max_speed_m_s * (time lost) of its last estimate, within
  /// `reacquire_window_s`, is the target again and takes over its id (the id stays stable).
  double reacquire_radius_m = 1.0;
  double reacquire_window_s = 6.0;
  double reacquire_max_radius_m = 4.0;   ///< the search radius never grows beyond this (m)
  double reacquire_min_speed_m_s = 0.3;  ///< the candidate walks (static clutter does not)
};

/// One person's filter: state X = [x, vx, y, vy] (seed's A with period T), measurement [x, y].
struct Track {
  std::uint32_t id = 0;
  Eigen::Vector4d state = Eigen::Vector4d::Zero();  ///< [x, vx, y, vy]
  Eigen::Matrix4d covariance = Eigen::Matrix4d::Identity();
  int hits = 0;              ///< updates with a detection
  int missed_frames = 0;     ///< consecutive frames without a detection
  double last_update_s = 0;  ///< time of the last detection
  double stamp_s = 0;        ///< time of the state
  double born_s = 0;         ///< time of the first detection
  bool confirmed = false;

  Eigen::Vector2d position() const { return {state[0], state[2]}; }
  Eigen::Vector2d velocity() const { return {state[1], state[3]}; }
};

/// Seed 000, step 5: X(k|k-1) = A X(k-1), P(k|k-1) = A P A' + Q with period T = dt_s.
void kalman_predict(Track& track, double dt_s, double accel_sigma_m_s2);
/// X(k|k) = X(k|k-1) + K (Z - H X(k|k-1)), K = P H' (H P H' + R)^-1, P = (I - K H) P.
void kalman_update(Track& track, const Eigen::Vector2d& z_m, double measurement_sigma_m);

struct TrackerUpdate {
  std::vector<std::int64_t> track_of_detection;  ///< per detection: track id, or -1 (unused)
  bool target_updated = false;                   ///< the target got a detection this frame
};

class PersonTracker {
 public:
  explicit PersonTracker(const TrackerConfig& config = {});

  /// One frame: predict all tracks to `stamp_s`, associate `detections_m` (fixed frame), update,
  /// create, confirm and delete tracks. Stamps must not decrease.
  TrackerUpdate update(double stamp_s, std::span<const Eigen::Vector2d> detections_m);

  const std::vector<Track>& tracks() const { return tracks_; }
  const Track* find(std::uint32_t id) const;

  /// Chooses the person to follow (seed 000, step 4). False when no confirmed track has `id`.
  bool select_target(std::uint32_t id);
  /// Chooses the confirmed track nearest to `point_m` (e.g. the one in front of the robot).
  std::optional<std::uint32_t> select_nearest(const Eigen::Vector2d& point_m);
  std::optional<std::uint32_t> target_id() const { return target_id_; }
  /// The target while it is tracked and not lost (missed at most coast_frames frames).
  const Track* target() const;
  /// True when a target was chosen but is currently lost (missed or deleted).
  bool target_lost() const { return target_id_.has_value() && target() == nullptr; }
  void clear_target() { target_id_.reset(); }

  const TrackerConfig& config() const { return config_; }

 private:
  TrackerConfig config_;
  std::vector<Track> tracks_;
  std::uint32_t next_id_ = 1;
  double stamp_s_ = 0;
  bool started_ = false;
  std::optional<std::uint32_t> target_id_;
  Eigen::Vector2d target_last_m_ = Eigen::Vector2d::Zero();
  double target_last_s_ = 0;
};

}  // namespace fieldlidar::people
