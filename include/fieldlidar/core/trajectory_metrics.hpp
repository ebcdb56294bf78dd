#pragma once
/// \file Accuracy of an estimated trajectory against a reference, as the KITTI odometry devkit
/// and `evo` report it: drift over sub-sequences of given lengths, relative pose error per frame
/// and absolute trajectory error after an SE(3) or Sim(3) (Umeyama) alignment.
///
/// Both trajectories are frame-indexed: pose i of the estimate and pose i of the reference are of
/// the same instant (match them by time before, e.g. with match_by_time). Poses are T_world_sensor.

#include <cstddef>
#include <vector>

#include "fieldlidar/core/pose.hpp"

namespace fieldlidar {

/// Summary of a set of non-negative errors (units of the errors).
struct ErrorStats {
  std::size_t count = 0;
  double mean = 0.0;
  double rmse = 0.0;
  double median = 0.0;  ///< the mean of the two middle values for an even count, as numpy's
  double max = 0.0;
  double std_dev = 0.0;  ///< population standard deviation, as evo's `std`
};
ErrorStats error_stats(std::vector<double> errors);

/// Settings of the trajectory evaluation.
struct TrajectoryMetricsConfig {
  /// Sub-sequence lengths of the KITTI drift metric (m, along the reference path); empty: chosen
  /// from the reference's path length by choose_segment_lengths.
  std::vector<double> segment_lengths_m;
  std::size_t segment_step_frames = 10;  ///< first frames of the sub-sequences (KITTI: 10)
  std::size_t rpe_delta_frames = 1;      ///< frame gap of the relative pose error (evo: 1)
  /// Re-project every rotation block onto SO(3) first, so that rounding in pose files (7 digits)
  /// adds no error floor.
  bool project_rotations = true;
};

/// Drift over the sub-sequences of one length.
struct SegmentLengthDrift {
  double length_m = 0.0;
  std::size_t segment_count = 0;
  double translation_pct = 0.0;     ///< mean translation error over the length (%)
  double rotation_deg_per_m = 0.0;  ///< mean rotation error per metre (deg/m)
};

/// The KITTI odometry metric: translation (%) and rotation (deg/m) errors of the relative motion
/// over every sub-sequence (start every `segment_step_frames` frames, end where the reference
/// path first exceeds the length), averaged over all sub-sequences of all lengths.
struct KittiDrift {
  std::vector<double> lengths_m;  ///< the lengths used
  std::vector<SegmentLengthDrift> per_length;
  std::size_t segment_count = 0;  ///< 0 when no length fits into the reference path
  double translation_pct = 0.0;
  double rotation_deg_per_m = 0.0;
};

/// Relative pose error over `rpe_delta_frames` frames (evo_rpe): for every i, the error of the
/// estimate's motion from i to i + delta against the reference's.
struct RelativePoseError {
  std::size_t delta_frames = 1;
  ErrorStats translation_m;
  ErrorStats rotation_deg;
};

/// A similarity transform mapping estimate positions into the reference frame:
/// p_ref ~= scale * rotation * p_est + translation.
struct Alignment {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  double scale = 1.0;
};

/// Absolute trajectory error (evo_ape, translation part) after an alignment.
struct AbsoluteTrajectoryError {
  Alignment alignment;
  ErrorStats translation_m;
};

struct TrajectoryMetrics {
  std::size_t pose_count = 0;
  double estimate_path_m = 0.0;
  double reference_path_m = 0.0;
  KittiDrift drift;
  RelativePoseError rpe;
  AbsoluteTrajectoryError ate_unaligned;  ///< no alignment (both start where they start)
  AbsoluteTrajectoryError ate_se3;        ///< rigid alignment (evo_ape -a)
  AbsoluteTrajectoryError ate_sim3;       ///< rigid + scale alignment (evo_ape -as)
};

/// All metrics. Throws fieldlidar::Error when the sizes differ, there are fewer than 2 poses or
/// not more than rpe_delta_frames, a pose is not finite, translated beyond 1e9 m (where the
/// metrics overflow) or its rotation block is far from a rotation (naming which pose).
TrajectoryMetrics evaluate_trajectory(const std::vector<Pose>& estimate,
                                      const std::vector<Pose>& reference,
                                      const TrajectoryMetricsConfig& config = {});

/// The rotation nearest to `m` in the Frobenius norm (SVD, determinant forced to +1).
Eigen::Matrix3d nearest_rotation(const Eigen::Matrix3d& m);
/// Copies of `poses` with every rotation block replaced by its nearest rotation.
std::vector<Pose> project_rotations(const std::vector<Pose>& poses);
/// Angle (rad) of a rotation matrix, accurate for small angles too.
double rotation_angle_rad(const Eigen::Matrix3d& rotation);
/// Cumulative path length at every pose (m), starting at 0.
std::vector<double> cumulative_path_m(const std::vector<Pose>& poses);

/// Lengths for the KITTI metric that fit a path: the devkit's 100, 200, ..., 800 m for paths of
/// 1000 m or more; otherwise a step of 1, 2 or 5 times a power of ten no longer than a tenth of
/// the path, and its multiples up to 0.7 of the path (at most ten): 146 m gives 10, 20, ..., 100
/// m, 18 m gives 1, 2, ..., 10 m. Empty for a path of zero length.
std::vector<double> choose_segment_lengths(double path_length_m);

KittiDrift kitti_drift(const std::vector<Pose>& estimate, const std::vector<Pose>& reference,
                       const std::vector<double>& lengths_m, std::size_t step_frames = 10);
RelativePoseError relative_pose_error(const std::vector<Pose>& estimate,
                                      const std::vector<Pose>& reference,
                                      std::size_t delta_frames = 1);
/// Least-squares alignment of the estimate's positions onto the reference's (Umeyama 1991), with
/// or without scale. A stationary estimate gets only the centroid shift.
Alignment align_positions(const std::vector<Pose>& estimate, const std::vector<Pose>& reference,
                          bool with_scale);
AbsoluteTrajectoryError absolute_trajectory_error(const std::vector<Pose>& estimate,
                                                  const std::vector<Pose>& reference,
                                                  const Alignment& alignment);

}  // namespace fieldlidar
