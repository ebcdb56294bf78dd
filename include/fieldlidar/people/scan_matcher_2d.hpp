#pragma once
/// \file Ego-motion of a 2D laser from its own scans: trimmed point-to-line ICP between
/// consecutive scans. For recordings without odometry (a bag of scans only): the person tracker
/// and the static background need detections in a fixed frame, and a moving robot sees its
/// furniture move in the sensor frame. With wheel odometry or a SLAM pose available, use that.
///
/// Frames: scan points in the sensor frame (x forward, y left, m). Poses are 2D rigid transforms
/// sensor -> fixed frame, where the fixed frame is the sensor frame of the first scan.

#include <cstddef>
#include <optional>
#include <span>
#include <vector>

#include <Eigen/Geometry>

namespace fieldlidar::people {

struct ScanMatcher2DConfig {
  int max_iterations = 30;
  /// Correspondences farther apart than this are ignored in the first iteration (m); the limit
  /// shrinks towards `min_correspondence_m` as the alignment converges.
  double max_correspondence_m = 0.5;
  double min_correspondence_m = 0.1;
  /// Iteration stops when the update is below these (m, rad).
  double converged_translation_m = 1e-4;
  double converged_rotation_rad = 1e-4;
  /// Scans are thinned to one point per this spacing along the scan before matching (m).
  double subsample_m = 0.05;
  double max_range_m = 20.0;  ///< points beyond this are not used (m)
  /// A match is refused (the motion prediction is kept) when, after the last iteration, fewer
  /// than this share of the current scan's points have a correspondence within
  /// min_correspondence_m.
  double min_inlier_fraction = 0.3;
  /// ScanOdometry2D: a match implying a faster motion than these since the previous scan is
  /// refused (the motion prediction is kept): a sensor on a mower or a person-following robot
  /// moves at walking pace, and a pitching 2D laser's ground line, which travels with the robot,
  /// can pull the match away by metres a scan (m/s, rad/s; 0 = no bound).
  double max_speed_m_s = 3.0;
  double max_turn_rate_rad_s = 3.0;
  /// ... and one whose velocity differs from the last believed match's by more than this times
  /// the time since that match (m/s^2; 0 = no bound): a robot brakes and speeds up within a few
  /// m/s^2, a ground line's pull jumps by metres a second.
  double max_accel_m_s2 = 6.0;
};

struct ScanMatch {
  Eigen::Isometry2d transform = Eigen::Isometry2d::Identity();  ///< current -> previous sensor
  double inlier_fraction = 0;  ///< share of current points with a close correspondence
  double rms_m = 0;            ///< rms distance of those correspondences (m)
  int iterations = 0;
  bool ok = false;        ///< false when too few points or inliers (transform = initial guess)
  bool too_fast = false;  ///< ScanOdometry2D: refused for the motion bounds (ok is false)
};

/// Aligns `current` to `previous` (both sensor-frame scans, m) starting from `initial_guess`
/// (current -> previous). Non-finite points are ignored.
ScanMatch match_scans_2d(std::span<const Eigen::Vector2d> previous,
                         std::span<const Eigen::Vector2d> current,
                         const Eigen::Isometry2d& initial_guess, const ScanMatcher2DConfig& config);

/// Scan-to-scan odometry: chains match_scans_2d over a scan sequence with a constant-velocity
/// initial guess. pose() is the current sensor pose in the frame of the first scan.
class ScanOdometry2D {
 public:
  explicit ScanOdometry2D(const ScanMatcher2DConfig& config = {});
  /// Adds the next scan (sensor frame), taken `dt_s` after the previous one (0: unknown, the
  /// motion bound is not applied), and returns its pose in the fixed frame.
  const Eigen::Isometry2d& add(std::span<const Eigen::Vector2d> scan, double dt_s = 0);
  const Eigen::Isometry2d& pose() const { return pose_; }
  const ScanMatch& last_match() const { return last_; }
  std::size_t failed_matches() const { return failed_; }

 private:
  ScanMatcher2DConfig config_;
  std::vector<Eigen::Vector2d> previous_;
  Eigen::Isometry2d pose_ = Eigen::Isometry2d::Identity();
  Eigen::Isometry2d last_step_ = Eigen::Isometry2d::Identity();
  ScanMatch last_;
  std::size_t failed_ = 0;
  bool started_ = false;
  std::optional<Eigen::Vector2d> believed_velocity_;  ///< of the last match believed (m/s)
  double refused_s_ = 0;                              ///< time since that match (s)
  /// A step (current -> previous sensor) over `dt_s` beyond the config's motion bounds.
  bool implausible(const Eigen::Isometry2d& step, double dt_s) const;
};

}  // namespace fieldlidar::people
