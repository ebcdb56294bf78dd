#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/core/trajectory_metrics.hpp"

using namespace fieldlidar;

namespace {

constexpr double kPi = std::numbers::pi;

/// A smooth drive: 1 m per frame along a gentle S-curve with some roll, pitch and height.
std::vector<Pose> s_curve(std::size_t n) {
  std::vector<Pose> poses;
  double x = 0.0, y = 0.0, yaw = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double t = static_cast<double>(i);
    poses.push_back(make_pose(x, y, 0.3 * std::sin(0.05 * t), 0.02 * std::sin(0.1 * t),
                              0.01 * std::cos(0.07 * t), yaw));
    yaw += 0.04 * std::sin(0.03 * t);
    x += std::cos(yaw);
    y += std::sin(yaw);
  }
  return poses;
}

/// A straight line along x, `step_m` per frame, no rotation.
std::vector<Pose> straight(std::size_t n, double step_m) {
  std::vector<Pose> poses;
  for (std::size_t i = 0; i < n; ++i)
    poses.push_back(make_pose(step_m * static_cast<double>(i), 0, 0, 0, 0, 0));
  return poses;
}

/// Every matrix entry printed with 7 significant digits, as in a KITTI poses file.
Pose rounded(const Pose& p) {
  Pose out = p;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) {
      char buf[32];
      std::snprintf(buf, sizeof(buf), "%.6e", p.matrix()(r, c));
      out.matrix()(r, c) = std::strtod(buf, nullptr);
    }
  return out;
}

}  // namespace

TEST(TrajectoryMetrics, ErrorStatsOfKnownValues) {
  const ErrorStats s = error_stats({4.0, 1.0, 3.0, 2.0});
  EXPECT_EQ(s.count, 4u);
  EXPECT_DOUBLE_EQ(s.mean, 2.5);
  EXPECT_DOUBLE_EQ(s.median, 2.5);
  EXPECT_DOUBLE_EQ(s.rmse, std::sqrt(7.5));
  EXPECT_DOUBLE_EQ(s.max, 4.0);
  EXPECT_NEAR(s.std_dev, std::sqrt(1.25), 1e-12);
  EXPECT_DOUBLE_EQ(error_stats({3.0, 1.0, 2.0}).median, 2.0);
  EXPECT_EQ(error_stats({}).count, 0u);
}

TEST(TrajectoryMetrics, SelfInAnotherWorldFrameHasNoError) {
  const std::vector<Pose> ref = s_curve(300);
  const Pose t_other_world = make_pose(12.0, -40.0, 3.0, 0.1, -0.2, 2.5);
  std::vector<Pose> est;
  for (const auto& p : ref) est.push_back(t_other_world * p);
  const TrajectoryMetrics m = evaluate_trajectory(est, ref);
  EXPECT_EQ(m.pose_count, 300u);
  EXPECT_NEAR(m.estimate_path_m, m.reference_path_m, 1e-9);
  EXPECT_GT(m.drift.segment_count, 100u);
  EXPECT_LT(m.drift.translation_pct, 1e-9);
  EXPECT_LT(m.drift.rotation_deg_per_m, 1e-9);
  EXPECT_LT(m.rpe.translation_m.max, 1e-9);
  EXPECT_LT(m.rpe.rotation_deg.max, 1e-9);
  EXPECT_GT(m.ate_unaligned.translation_m.rmse, 10.0);
  EXPECT_LT(m.ate_se3.translation_m.rmse, 1e-9);
  EXPECT_LT(m.ate_sim3.translation_m.rmse, 1e-9);
  EXPECT_NEAR(m.ate_sim3.alignment.scale, 1.0, 1e-9);
  // The alignment is the inverse of the frame change.
  EXPECT_LT((m.ate_se3.alignment.rotation - t_other_world.linear().transpose()).norm(), 1e-9);
}

TEST(TrajectoryMetrics, Sim3AlignmentRecoversTheScale) {
  const std::vector<Pose> ref = s_curve(200);
  const double scale = 0.97;  // the estimate is 3 % short
  const Pose t_other_world = make_pose(-5.0, 8.0, 1.0, 0.0, 0.05, -1.0);
  std::vector<Pose> est;
  for (const auto& p : ref) {
    Pose q = p;
    q.translation() *= scale;
    est.push_back(t_other_world * q);
  }
  const TrajectoryMetrics m = evaluate_trajectory(est, ref);
  EXPECT_NEAR(m.estimate_path_m / m.reference_path_m, scale, 1e-9);
  EXPECT_NEAR(m.ate_sim3.alignment.scale, 1.0 / scale, 1e-9);
  EXPECT_LT(m.ate_sim3.translation_m.rmse, 1e-9);
  EXPECT_GT(m.ate_se3.translation_m.rmse, 0.1);  // a rigid alignment cannot undo the scale
  // A 3 % short estimate is off by 3 % of each segment's chord (in translation only): the chord is
  // shorter than the length on the curve, and longer by the end frame's overshoot (< 1 m).
  EXPECT_GT(m.drift.translation_pct, 2.5);
  EXPECT_LT(m.drift.translation_pct, 3.0 * 21.0 / 20.0);
  EXPECT_NEAR(m.drift.per_length.front().translation_pct, 3.0, 0.1);
  EXPECT_LT(m.drift.rotation_deg_per_m, 1e-9);
  EXPECT_NEAR(m.rpe.translation_m.mean, 0.03, 1e-3);  // 3 % of about 1 m per frame
}

TEST(TrajectoryMetrics, ConstantScaleDriftGivesTheKnownPercentage) {
  // 0.5 m per frame; the estimate moves 1 % too far. A segment of length L ends at the first
  // frame beyond L, i.e. L + 0.5 m along the reference: error 1 % of L + 0.5 m over L.
  const std::vector<Pose> ref = straight(401, 0.5);
  const std::vector<Pose> est = straight(401, 0.505);
  TrajectoryMetricsConfig cfg;
  cfg.segment_lengths_m = {10.0, 50.0};
  const TrajectoryMetrics m = evaluate_trajectory(est, ref, cfg);
  // Start frames 0, 10, ..., 400; length 10 ends 21 frames later, so fits while first <= 379
  // (38 starts); 50 ends 101 frames later, fits while first <= 299 (30 starts).
  ASSERT_EQ(m.drift.per_length.size(), 2u);
  EXPECT_EQ(m.drift.per_length[0].segment_count, 38u);
  EXPECT_EQ(m.drift.per_length[1].segment_count, 30u);
  EXPECT_NEAR(m.drift.per_length[0].translation_pct, 1.0 * 10.5 / 10.0, 1e-9);
  EXPECT_NEAR(m.drift.per_length[1].translation_pct, 1.0 * 50.5 / 50.0, 1e-9);
  const double expected = (38 * 1.05 + 30 * 1.01) / 68.0;
  EXPECT_NEAR(m.drift.translation_pct, expected, 1e-9);
  EXPECT_EQ(m.drift.segment_count, 68u);
  EXPECT_NEAR(m.ate_sim3.alignment.scale, 0.5 / 0.505, 1e-9);
}

TEST(TrajectoryMetrics, ConstantHeadingDriftGivesTheKnownRate) {
  // Same positions, the estimate's heading turns 0.01 deg per frame (1 m): a segment of L ends
  // L + 1 frames later, so its rotation error is 0.01 (L + 1) / L deg per metre.
  const std::vector<Pose> ref = straight(301, 1.0);
  std::vector<Pose> est;
  for (std::size_t i = 0; i < ref.size(); ++i)
    est.push_back(
        make_pose(static_cast<double>(i), 0, 0, 0, 0, 0.01 * kPi / 180.0 * static_cast<double>(i)));
  TrajectoryMetricsConfig cfg;
  cfg.segment_lengths_m = {20.0};
  const TrajectoryMetrics m = evaluate_trajectory(est, ref, cfg);
  EXPECT_NEAR(m.drift.rotation_deg_per_m, 0.01 * 21.0 / 20.0, 1e-9);
  EXPECT_NEAR(m.rpe.rotation_deg.mean, 0.01, 1e-9);
  EXPECT_NEAR(m.rpe.rotation_deg.median, 0.01, 1e-9);
}

TEST(TrajectoryMetrics, RelativePoseErrorOfAKnownJitter) {
  // Every odd frame is off by 2 cm sideways in its own frame: every consecutive pair is 2 cm off.
  const std::vector<Pose> ref = s_curve(101);
  std::vector<Pose> est = ref;
  Pose jitter = Pose::Identity();
  jitter.translation() = Eigen::Vector3d(0.0, 0.02, 0.0);
  for (std::size_t i = 1; i < est.size(); i += 2) est[i] = est[i] * jitter;
  const RelativePoseError rpe = relative_pose_error(est, ref, 1);
  EXPECT_EQ(rpe.translation_m.count, 100u);
  EXPECT_NEAR(rpe.translation_m.mean, 0.02, 1e-12);
  EXPECT_NEAR(rpe.translation_m.rmse, 0.02, 1e-12);
  EXPECT_NEAR(rpe.translation_m.median, 0.02, 1e-12);
  EXPECT_LT(rpe.rotation_deg.max, 1e-9);
  // On a straight line, over 2 frames, the jitter cancels.
  const std::vector<Pose> line = straight(101, 1.0);
  std::vector<Pose> line_est = line;
  for (std::size_t i = 1; i < line_est.size(); i += 2) line_est[i] = line_est[i] * jitter;
  const RelativePoseError rpe2 = relative_pose_error(line_est, line, 2);
  EXPECT_EQ(rpe2.translation_m.count, 99u);
  EXPECT_LT(rpe2.translation_m.max, 1e-12);
}

TEST(TrajectoryMetrics, KittiDriftMatchesABruteForceOracle) {
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 1.0);
  const std::vector<Pose> ref = s_curve(250);
  std::vector<Pose> est;
  Pose drift = Pose::Identity();
  for (const auto& p : ref) {
    est.push_back(drift * p);
    drift = drift * make_pose(0.01 * noise(rng), 0.01 * noise(rng), 0.005 * noise(rng),
                              0.001 * noise(rng), 0.001 * noise(rng), 0.002 * noise(rng));
  }
  const std::vector<double> lengths = {5.0, 17.5, 60.0, 200.0};
  const KittiDrift d = kitti_drift(est, ref, lengths, 7);

  // Oracle: full 4x4 inverses, path lengths summed afresh for every candidate end frame, angle
  // from the angle-axis decomposition.
  double sum_t = 0.0, sum_r = 0.0;
  std::size_t count = 0;
  for (std::size_t first = 0; first < ref.size(); first += 7)
    for (double length : lengths)
      for (std::size_t last = first + 1; last < ref.size(); ++last) {
        double dist = 0.0;
        for (std::size_t k = first + 1; k <= last; ++k)
          dist += (ref[k].translation() - ref[k - 1].translation()).norm();
        if (dist <= length) continue;
        const Eigen::Matrix4d dr = ref[first].matrix().inverse() * ref[last].matrix();
        const Eigen::Matrix4d de = est[first].matrix().inverse() * est[last].matrix();
        const Eigen::Matrix4d e = de.inverse() * dr;
        sum_t += e.topRightCorner<3, 1>().norm() / length;
        sum_r += Eigen::AngleAxisd(Eigen::Matrix3d(e.topLeftCorner<3, 3>())).angle() * 180.0 / kPi /
                 length;
        ++count;
        break;
      }
  ASSERT_GT(count, 50u);
  EXPECT_EQ(d.segment_count, count);
  EXPECT_NEAR(d.translation_pct, 100.0 * sum_t / static_cast<double>(count), 1e-9);
  EXPECT_NEAR(d.rotation_deg_per_m, sum_r / static_cast<double>(count), 1e-9);
  EXPECT_GT(d.translation_pct, 0.1);
}

TEST(TrajectoryMetrics, RoundedPoseFilesAddNoErrorFloor) {
  const std::vector<Pose> ref = s_curve(200);
  std::vector<Pose> est;
  for (const auto& p : ref) est.push_back(rounded(p));
  const TrajectoryMetrics m = evaluate_trajectory(est, ref);
  EXPECT_LT(m.rpe.rotation_deg.max, 1e-4);
  EXPECT_LT(m.rpe.translation_m.max, 3e-4);  // 7 digits of a 200 m coordinate
  EXPECT_LT(m.drift.rotation_deg_per_m, 1e-5);
  const Eigen::Matrix3d r = nearest_rotation(est[57].linear());
  EXPECT_LT((r.transpose() * r - Eigen::Matrix3d::Identity()).norm(), 1e-14);
  EXPECT_NEAR(r.determinant(), 1.0, 1e-14);
  EXPECT_LT((r - ref[57].linear()).norm(), 1e-6);
  // A symmetric (stretching) perturbation of a rotation projects back onto it.
  const Eigen::Matrix3d stretched =
      ref[9].linear() * (Eigen::Matrix3d::Identity() +
                         1e-3 * Eigen::Vector3d(1, -2, 0.5).asDiagonal().toDenseMatrix());
  EXPECT_LT((nearest_rotation(stretched) - ref[9].linear()).norm(), 1e-12);
}

TEST(TrajectoryMetrics, ChoosesSegmentLengthsThatFit) {
  const std::vector<double> greenhouse = choose_segment_lengths(146.0);
  ASSERT_EQ(greenhouse.size(), 10u);
  EXPECT_DOUBLE_EQ(greenhouse.front(), 10.0);
  EXPECT_DOUBLE_EQ(greenhouse.back(), 100.0);
  const std::vector<double> short_drive = choose_segment_lengths(18.0);
  ASSERT_EQ(short_drive.size(), 10u);
  EXPECT_DOUBLE_EQ(short_drive.front(), 1.0);
  EXPECT_DOUBLE_EQ(short_drive.back(), 10.0);
  EXPECT_EQ(choose_segment_lengths(1500.0),
            (std::vector<double>{100, 200, 300, 400, 500, 600, 700, 800}));
  EXPECT_EQ(choose_segment_lengths(30.0),
            (std::vector<double>{2, 4, 6, 8, 10, 12, 14, 16, 18, 20}));
  EXPECT_TRUE(choose_segment_lengths(0.0).empty());
  // Every chosen length leaves room for segments.
  for (double path : {0.3, 7.0, 42.0, 999.0})
    for (double l : choose_segment_lengths(path)) EXPECT_LE(l, 0.7 * path);
}

TEST(TrajectoryMetrics, StationaryEstimateIsAlignedByItsCentroid) {
  const std::vector<Pose> ref = straight(10, 1.0);
  const std::vector<Pose> est(10, Pose::Identity());
  const TrajectoryMetrics m = evaluate_trajectory(est, ref);
  EXPECT_DOUBLE_EQ(m.estimate_path_m, 0.0);
  EXPECT_NEAR(m.ate_se3.alignment.translation.x(), 4.5, 1e-12);
  EXPECT_NEAR(m.ate_sim3.alignment.scale, 1.0, 1e-12);
  EXPECT_NEAR(m.ate_se3.translation_m.mean, 2.5, 1e-12);
}

TEST(TrajectoryMetrics, BadInputIsAnError) {
  const std::vector<Pose> ref = straight(10, 1.0);
  EXPECT_THROW(evaluate_trajectory(straight(9, 1.0), ref), Error);
  EXPECT_THROW(evaluate_trajectory(straight(1, 1.0), straight(1, 1.0)), Error);
  std::vector<Pose> nan = ref;
  nan[4].translation().x() = std::nan("");
  EXPECT_THROW(evaluate_trajectory(nan, ref), Error);
  std::vector<Pose> skew = ref;
  skew[3].linear() *= 2.0;
  EXPECT_THROW(evaluate_trajectory(ref, skew), Error);
  TrajectoryMetricsConfig cfg;
  cfg.segment_lengths_m = {5.0, -1.0};
  EXPECT_THROW(evaluate_trajectory(ref, ref, cfg), Error);
  try {
    evaluate_trajectory(nan, ref);
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("estimate pose 4"), std::string::npos) << e.what();
  }
}
