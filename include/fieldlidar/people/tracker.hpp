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
  /// Re-acquisition after a loss (occlusion behind a shed or a hedge, a missed turn). Within
  /// `target_reattach_s` of its last detection the target's own track may take a detection again
  /// (a leg missed for a sweep or two). After that the old track is dropped (a coasting track
  /// would take whatever lies along its prediction, e.g. clutter at the occluder's corner) and the
  /// mower stays stopped until a confirmed re-acquisition: a track born after the loss that
  /// walks (moved `reacquire_min_walk_m` from where it was born, at `reacquire_min_speed_m_s` or
  /// more; static clutter does not), within `reacquire_window_s` of the loss and within reach of
  /// a walking person, reacquire_radius_m + reacquire_walk_speed_m_s * (time lost), never beyond
  /// reacquire_max_radius_m, of the last estimate. Of several, the one nearest the lost track's
  /// straight-on path (last position + velocity * time lost, or any point short of it) is the
  /// target again and takes over its id (the id stays stable). People tracked since before the
  /// loss away from the target (farther than reacquire_radius_m) are never candidates; a track
  /// beside it (a duplicate on one of its legs) may be.
  double target_reattach_s = 0.5;
  double reacquire_radius_m = 1.0;
  double reacquire_window_s = 15.0;
  double reacquire_walk_speed_m_s = 1.5;  ///< how fast a person walks while hidden (m/s)
  double reacquire_max_radius_m = 10.0;   ///< the search radius never grows beyond this (m)
  double reacquire_min_speed_m_s = 0.3;   ///< the candidate walks (static clutter does not)
  double reacquire_min_walk_m = 1.0;      ///< and has moved this far since it was born (m)
  int reacquire_min_streak = 10;          ///< over this many frames in a row (clutter flickers)
};

/// One person's filter: state X = [x, vx, y, vy] (seed's A with period T), measurement [x, y].
struct Track {
  std::uint32_t id = 0;
  Eigen::Vector4d state = Eigen::Vector4d::Zero();  ///< [x, vx, y, vy]
  Eigen::Matrix4d covariance = Eigen::Matrix4d::Identity();
  int hits = 0;              ///< updates with a detection
  int missed_frames = 0;     ///< consecutive frames without a detection
  int streak = 1;            ///< consecutive frames with a detection, up to the last one
  double last_update_s = 0;  ///< time of the last detection
  double stamp_s = 0;        ///< time of the state
  double born_s = 0;         ///< time of the first detection
  Eigen::Vector2d born_m = Eigen::Vector2d::Zero();  ///< position of the first detection
  bool confirmed = false;

  Eigen::Vector2d position() const { return {state[0], state[2]}; }
  Eigen::Vector2d velocity() const { return {state[1], state[3]}; }
};

/// Seed 000, step 5: X(k|k-1) = A X(k-1), P(k|k-1) = A P A' + Q with period T = dt_s.
void kalman_predict(Track& track, double dt_s, double accel_sigma_m_s2);
/// X(k|k) = X(k|k-1) + K (Z - H X(k|k-1)), K = P H' (H P H' + R)^-1, P = (I - K H) P.
void kalman_update(Track& track, const Eigen::Vector2d& z_m, double measurement_sigma_m);

/// The track walks as a re-acquisition asks (TrackerConfig::reacquire_min_*): seen in
/// reacquire_min_streak frames in a row, at reacquire_min_speed_m_s or more, and
/// reacquire_min_walk_m from where it was born (static clutter neither keeps a speed nor moves
/// away from where it was born).
bool walks(const Track& track, const TrackerConfig& config);

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
  /// Seconds since the target's last detection (0 while it is tracked or none was chosen).
  double target_lost_s() const { return target_lost() ? stamp_s_ - target_last_s_ : 0.0; }
  /// Where the target was last detected (m, fixed frame).
  const Eigen::Vector2d& target_last_m() const { return target_last_m_; }
  /// Where the lost target would be now had it walked on at its last velocity (m, fixed frame).
  Eigen::Vector2d target_predicted_m() const {
    return target_last_m_ + target_last_v_ * target_lost_s();
  }
  /// A confirmed track born after the target was lost that walks (see TrackerConfig): the only
  /// kind of track that may become the lost target again.
  bool may_reacquire(const Track& track) const;
  /// The lost target is track `id` again (e.g. the operator walked back in front of the mower
  /// after the re-acquisition window): `id` takes over the target's id. False, and nothing
  /// changes, unless the target is lost and may_reacquire() holds for `id`.
  bool reacquire(std::uint32_t id);
  /// The lost target is track `id` again on the detector's word: a detector that tracks people
  /// itself reports the target's own person again (after a few scans without legs, say), so
  /// `id` takes over the target's id and counts as confirmed, whether or not it walks. False,
  /// and nothing changes, unless the target is lost and `id` is a track updated this frame.
  bool retake(std::uint32_t id);

  const TrackerConfig& config() const { return config_; }

 private:
  /// The confirmed, walking track that re-acquires the lost target now, if any.
  const Track* reacquisition_candidate(double stamp_s) const;
  /// Remembers the tracks away from `target` (see others_at_loss_).
  void note_others(const Track& target);
  /// The track `id` takes the target's id and last position, velocity and time; the target's
  /// own (coasting) track goes.
  void take_as_target(std::uint32_t id);

  TrackerConfig config_;
  std::vector<Track> tracks_;
  std::uint32_t next_id_ = 1;
  double stamp_s_ = 0;
  bool started_ = false;
  std::optional<std::uint32_t> target_id_;
  Eigen::Vector2d target_last_m_ = Eigen::Vector2d::Zero();
  Eigen::Vector2d target_last_v_ = Eigen::Vector2d::Zero();
  /// The tracks other than the target, away from it, when it was last detected: other people
  /// (or clutter) that may never take over the target's id.
  std::vector<std::uint32_t> others_at_loss_;
  double target_last_s_ = 0;
};

}  // namespace fieldlidar::people
