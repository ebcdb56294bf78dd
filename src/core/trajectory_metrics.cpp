#include "fieldlidar/core/trajectory_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include <Eigen/Geometry>
#include <Eigen/SVD>

#include "fieldlidar/core/error.hpp"

namespace fieldlidar {

namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;
/// Farther than any ground trajectory goes (the Moon is 3.8e8 m away) and far below where the
/// sums of squared errors and the alignment's covariance overflow (|t| ~ 1e150 m): a translation
/// beyond it is a broken file, and would give inf or NaN metrics, or a Sim(3) scale of 0.
constexpr double kMaxTranslationM = 1e9;

void check_poses(const std::vector<Pose>& poses, const char* name) {
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const auto& m = poses[i].matrix();
    if (!m.allFinite())
      throw Error(std::string(name) + " pose " + std::to_string(i) + " is not finite (NaN or inf)");
    const double t = poses[i].translation().cwiseAbs().maxCoeff();
    if (t > kMaxTranslationM)
      throw Error(std::string(name) + " pose " + std::to_string(i) + ": translation " +
                  short_number(t) + " m is beyond " + short_number(kMaxTranslationM) + " m");
    const Eigen::Matrix3d r = poses[i].linear();
    const double off = (r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
    if (off > 1e-2 || r.determinant() <= 0.0)
      throw Error(std::string(name) + " pose " + std::to_string(i) +
                  ": the 3x3 block is not a rotation (|R^T R - I| = " + std::to_string(off) +
                  ", det = " + std::to_string(r.determinant()) + ")");
  }
}

/// The relative motion from pose i to pose j of a trajectory.
Pose motion(const std::vector<Pose>& poses, std::size_t i, std::size_t j) {
  return poses[i].inverse(Eigen::Isometry) * poses[j];
}

/// Largest of 1, 2, 5 times a power of ten that is <= x (x > 0).
double nice_floor(double x) {
  const double decade = std::pow(10.0, std::floor(std::log10(x)));
  for (double f : {5.0, 2.0, 1.0})
    if (f * decade <= x * (1.0 + 1e-12)) return f * decade;
  return decade;
}

}  // namespace

ErrorStats error_stats(std::vector<double> errors) {
  ErrorStats s;
  s.count = errors.size();
  if (errors.empty()) return s;
  double sum = 0.0, sum_sq = 0.0;
  for (double e : errors) {
    sum += e;
    sum_sq += e * e;
    s.max = std::max(s.max, e);
  }
  const double n = static_cast<double>(errors.size());
  s.mean = sum / n;
  s.rmse = std::sqrt(sum_sq / n);
  s.std_dev = std::sqrt(std::max(0.0, sum_sq / n - s.mean * s.mean));
  const std::size_t mid = errors.size() / 2;
  std::nth_element(errors.begin(), errors.begin() + static_cast<std::ptrdiff_t>(mid), errors.end());
  s.median = errors[mid];
  if (errors.size() % 2 == 0)
    s.median =
        0.5 * (s.median + *std::max_element(errors.begin(),
                                            errors.begin() + static_cast<std::ptrdiff_t>(mid)));
  return s;
}

Eigen::Matrix3d nearest_rotation(const Eigen::Matrix3d& m) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(m, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
  d(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0 ? -1.0 : 1.0;
  return svd.matrixU() * d * svd.matrixV().transpose();
}

std::vector<Pose> project_rotations(const std::vector<Pose>& poses) {
  std::vector<Pose> out = poses;
  for (auto& p : out) p.linear() = nearest_rotation(p.linear());
  return out;
}

double rotation_angle_rad(const Eigen::Matrix3d& r) {
  // atan2 of sin and cos keeps small angles exact where acos((trace - 1) / 2) would lose them.
  const Eigen::Vector3d axis_sin(r(2, 1) - r(1, 2), r(0, 2) - r(2, 0), r(1, 0) - r(0, 1));
  return std::atan2(0.5 * axis_sin.norm(), 0.5 * (r.trace() - 1.0));
}

std::vector<double> cumulative_path_m(const std::vector<Pose>& poses) {
  std::vector<double> dist(poses.size(), 0.0);
  for (std::size_t i = 1; i < poses.size(); ++i)
    dist[i] = dist[i - 1] + (poses[i].translation() - poses[i - 1].translation()).norm();
  return dist;
}

std::vector<double> choose_segment_lengths(double path_length_m) {
  if (!(path_length_m > 0.0)) return {};
  if (path_length_m >= 1000.0) return {100, 200, 300, 400, 500, 600, 700, 800};
  const double unit = nice_floor(path_length_m / 10.0);
  std::vector<double> lengths;
  for (int k = 1; k <= 10 && k * unit <= 0.7 * path_length_m; ++k) lengths.push_back(k * unit);
  return lengths;
}

KittiDrift kitti_drift(const std::vector<Pose>& estimate, const std::vector<Pose>& reference,
                       const std::vector<double>& lengths_m, std::size_t step_frames) {
  KittiDrift drift;
  drift.lengths_m = lengths_m;
  const std::vector<double> dist = cumulative_path_m(reference);
  const std::size_t n = reference.size();
  double sum_t = 0.0, sum_r = 0.0;
  for (double length : lengths_m) {
    SegmentLengthDrift d;
    d.length_m = length;
    for (std::size_t first = 0; first < n; first += std::max<std::size_t>(1, step_frames)) {
      // The devkit's lastFrameFromSegmentLength: the first frame beyond the length.
      const auto it = std::upper_bound(dist.begin() + static_cast<std::ptrdiff_t>(first),
                                       dist.end(), dist[first] + length);
      if (it == dist.end()) continue;
      const auto last = static_cast<std::size_t>(it - dist.begin());
      const Pose error =
          motion(estimate, first, last).inverse(Eigen::Isometry) * motion(reference, first, last);
      const double t = error.translation().norm() / length;
      const double r = rotation_angle_rad(error.linear()) * kDegPerRad / length;
      d.translation_pct += t;
      d.rotation_deg_per_m += r;
      ++d.segment_count;
      sum_t += t;
      sum_r += r;
      ++drift.segment_count;
    }
    if (d.segment_count > 0) {
      d.translation_pct *= 100.0 / static_cast<double>(d.segment_count);
      d.rotation_deg_per_m /= static_cast<double>(d.segment_count);
    }
    drift.per_length.push_back(d);
  }
  if (drift.segment_count > 0) {
    drift.translation_pct = 100.0 * sum_t / static_cast<double>(drift.segment_count);
    drift.rotation_deg_per_m = sum_r / static_cast<double>(drift.segment_count);
  }
  return drift;
}

RelativePoseError relative_pose_error(const std::vector<Pose>& estimate,
                                      const std::vector<Pose>& reference,
                                      std::size_t delta_frames) {
  RelativePoseError rpe;
  rpe.delta_frames = std::max<std::size_t>(1, delta_frames);
  std::vector<double> t_err, r_err;
  for (std::size_t i = 0; i + rpe.delta_frames < reference.size(); ++i) {
    const std::size_t j = i + rpe.delta_frames;
    const Pose error = motion(reference, i, j).inverse(Eigen::Isometry) * motion(estimate, i, j);
    t_err.push_back(error.translation().norm());
    r_err.push_back(rotation_angle_rad(error.linear()) * kDegPerRad);
  }
  rpe.translation_m = error_stats(std::move(t_err));
  rpe.rotation_deg = error_stats(std::move(r_err));
  return rpe;
}

Alignment align_positions(const std::vector<Pose>& estimate, const std::vector<Pose>& reference,
                          bool with_scale) {
  const auto n = static_cast<Eigen::Index>(std::min(estimate.size(), reference.size()));
  Eigen::Matrix3Xd src(3, n), dst(3, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    src.col(i) = estimate[static_cast<std::size_t>(i)].translation();
    dst.col(i) = reference[static_cast<std::size_t>(i)].translation();
  }
  Alignment a;
  if (n == 0) return a;
  const Eigen::Vector3d src_mean = src.rowwise().mean();
  const double src_spread = (src.colwise() - src_mean).squaredNorm();
  if (!(src_spread > 1e-18 * static_cast<double>(n))) {  // stationary: nothing to rotate or scale
    a.translation = dst.rowwise().mean() - src_mean;
    return a;
  }
  const Eigen::Matrix4d t = Eigen::umeyama(src, dst, with_scale);
  const Eigen::Matrix3d sr = t.topLeftCorner<3, 3>();
  a.scale = with_scale ? std::cbrt(sr.determinant()) : 1.0;
  a.rotation = sr / a.scale;
  a.translation = t.topRightCorner<3, 1>();
  return a;
}

AbsoluteTrajectoryError absolute_trajectory_error(const std::vector<Pose>& estimate,
                                                  const std::vector<Pose>& reference,
                                                  const Alignment& alignment) {
  AbsoluteTrajectoryError ate;
  ate.alignment = alignment;
  std::vector<double> errors;
  const std::size_t n = std::min(estimate.size(), reference.size());
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d p =
        alignment.scale * (alignment.rotation * estimate[i].translation()) + alignment.translation;
    errors.push_back((p - reference[i].translation()).norm());
  }
  ate.translation_m = error_stats(std::move(errors));
  return ate;
}

TrajectoryMetrics evaluate_trajectory(const std::vector<Pose>& estimate_in,
                                      const std::vector<Pose>& reference_in,
                                      const TrajectoryMetricsConfig& config) {
  if (estimate_in.size() != reference_in.size())
    throw Error("trajectory evaluation: the estimate has " + std::to_string(estimate_in.size()) +
                " poses but the reference " + std::to_string(reference_in.size()));
  if (estimate_in.size() < 2)
    throw Error("trajectory evaluation: " + std::to_string(estimate_in.size()) +
                " poses; at least 2 are needed");
  // No pair would leave the RPE at count 0 and rmse 0, which reads as a perfect estimate.
  if (config.rpe_delta_frames >= estimate_in.size())
    throw Error("trajectory evaluation: no RPE pair at a delta of " +
                std::to_string(config.rpe_delta_frames) + " frames in " +
                std::to_string(estimate_in.size()) + " poses");
  check_poses(estimate_in, "estimate");
  check_poses(reference_in, "reference");
  const std::vector<Pose> estimate =
      config.project_rotations ? project_rotations(estimate_in) : estimate_in;
  const std::vector<Pose> reference =
      config.project_rotations ? project_rotations(reference_in) : reference_in;

  TrajectoryMetrics m;
  m.pose_count = estimate.size();
  m.estimate_path_m = cumulative_path_m(estimate).back();
  m.reference_path_m = cumulative_path_m(reference).back();
  for (double length : config.segment_lengths_m)
    if (!(length > 0.0) || !std::isfinite(length))
      throw Error("trajectory evaluation: segment length " + std::to_string(length) +
                  " m is not a positive number");
  const std::vector<double> lengths = config.segment_lengths_m.empty()
                                          ? choose_segment_lengths(m.reference_path_m)
                                          : config.segment_lengths_m;
  m.drift = kitti_drift(estimate, reference, lengths, config.segment_step_frames);
  m.rpe = relative_pose_error(estimate, reference, config.rpe_delta_frames);
  m.ate_unaligned = absolute_trajectory_error(estimate, reference, Alignment{});
  m.ate_se3 =
      absolute_trajectory_error(estimate, reference, align_positions(estimate, reference, false));
  m.ate_sim3 =
      absolute_trajectory_error(estimate, reference, align_positions(estimate, reference, true));
  return m;
}

}  // namespace fieldlidar
