// Accuracy on kitti_tracking0000 (50 HDL-64E frames, LiDAR only) against the stereo ORB-SLAM3
// reference brought into the lidar frame: T_lidar = C^-1 T_cam C, C = R0_rect * Tr_velo_to_cam.

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "fieldlidar/io/cloud_file.hpp"
#include "fieldlidar/io/trajectory_io.hpp"
#include "odometry_eval.hpp"
#include "test_data.hpp"

namespace fieldlidar::odometry::test {
namespace {

Pose calib_C(const std::filesystem::path& calib) {
  std::ifstream in(calib);
  std::string line;
  Eigen::Matrix3d R0 = Eigen::Matrix3d::Identity();
  Pose Tr = Pose::Identity();
  while (std::getline(in, line)) {
    std::istringstream ss(line);
    std::string key;
    ss >> key;
    if (key == "R0_rect:")
      for (int i = 0; i < 9; ++i) ss >> R0(i / 3, i % 3);
    if (key == "Tr_velo_to_cam:")
      for (int i = 0; i < 12; ++i) ss >> Tr.matrix()(i / 4, i % 4);
  }
  Pose R = Pose::Identity();
  R.linear() = R0;
  return R * Tr;
}

struct KittiData {
  std::vector<PointCloud> frames;
  std::vector<Pose> reference;  ///< lidar frame, relative to frame 0
};

const KittiData& kitti() {
  static const KittiData data = [] {
    KittiData d;
    const auto dir = fieldlidar::test::data_dir() / "kitti_tracking0000";
    if (!std::filesystem::exists(dir)) return d;
    const Pose C = calib_C(dir / "calib.txt");
    const auto ref = io::read_kitti_poses(dir / "orbslam3_poses_0000_frames0-49.txt");
    for (int i = 0; i < 50; ++i) {
      char name[32];
      std::snprintf(name, sizeof name, "%010d.pcd", i);
      auto cloud = io::read_cloud(dir / "velodyne" / name);
      cloud.stamp_s = 0.1 * i;
      d.frames.push_back(std::move(cloud));
      d.reference.push_back(C.inverse() * ref[i].pose * C);
    }
    return d;
  }();
  return data;
}

OdometryConfig kitti_config() {
  OdometryConfig cfg;
  apply_env(cfg);
  return cfg;
}

/// Runs frames first, first+step, ... < last; errors against the reference of those frames.
TrajectoryErrors run_kitti(int first, int last, int step, const OdometryConfig& cfg,
                           bool scale = false, double* ms = nullptr) {
  const auto& d = kitti();
  LidarOdometry odo(SensorModel::hdl64e(), cfg);
  std::vector<Pose> est, ref;
  double total = 0;
  for (int i = first; i < last; i += step) {
    const auto r = odo.register_frame(d.frames[i]);
    total += r.timings.total_ms;
    est.push_back(r.T_world_lidar);
    ref.push_back(d.reference[i]);
  }
  if (ms) *ms = total / est.size();
  return trajectory_errors(est, relative_to_first(ref), 5.0, scale);
}

void report(const char* what, const TrajectoryErrors& e) {
  std::printf(
      "%-28s path %.3f of %.2f m (%.4f)  drift %.2f %%  RPE %.2f cm / %.3f deg  ATE %.3f m "
      "(Sim3 %.3f m)\n",
      what, e.est_path_m, e.path_m, e.est_path_m / e.path_m, e.drift_pct, 100 * e.rpe_t_m,
      e.rpe_r_deg, e.ate_se3_m, e.ate_sim3_m);
}

TEST(OdometryKitti, DISABLED_Report) {
  if (kitti().frames.empty()) GTEST_SKIP() << "kitti_tracking0000 not found";
  double ms = 0;
  report("frames 0-24 (tuning)", run_kitti(0, 25, 1, kitti_config()));
  report("frames 25-49 (test)", run_kitti(25, 50, 1, kitti_config()));
  report("frames 0-49", run_kitti(0, 50, 1, kitti_config(), false, &ms));
  std::printf("  %.1f ms per frame\n", ms);
  if (std::getenv("ONLYDEF")) return;
  for (int step : {2, 3, 5}) {
    char what[64];
    std::snprintf(what, sizeof what, "every %d. frame", step);
    report(what, run_kitti(0, 50, step, kitti_config()));
  }
}

// ATE 0.142 m, path 0.9715 of the reference's; after a similarity alignment 0.023 m. The error
// after a rigid alignment is along the track: +0.28 m at frame 0 falling steadily to -0.22 m at
// frame 49, across the track 0.01-0.06 m. It is the scale of the reference, not the odometry's:
// - the path ratio stays 0.9703-0.9722 with every setting tried (map voxel 0.5-1.5 m, 5-15 fit
//   points, point spacing 0.1-0.3 m, 16-60 planar points per sector, 1-20 edges, robust scale
//   0.05-0.3 m, feature ranges, ground split, clusters, the elevation correction of 0.22, 0.5
//   or 1 deg) and with every 2nd, 3rd or 5th frame (0.9711, 0.9712, 0.9703): a bias of each
//   registration would shrink with fewer of them;
// - on simulated HDL-64E drives like this one (18 m in 5 s, 38 deg turn, LiDAR only) the path
//   comes out 0.997-1.002 of the truth's (test_odometry_hdl64_scale.cpp);
// - the road plane ahead (4-15 m, 50 sweeps) lies 1.730 m below the sensor (sd 0.041 m), the
//   HDL-64E's mounting height on the KITTI car (1.73 m): the sweeps' own scale is right to about
//   1 %, where a 3 % short scan would put it at 1.68 m;
// - the seed's frame-to-frame matching finds 0.9650, as both peers find 3-4 % short.
// The reference scaled by 0.9715 scores 0.146 m against itself; 0.135 m would need a path ratio
// of 0.9735. De-skewing by azimuth (any start and sense, DeskewConfig::azimuth_start_deg)
// raises the rotation RPE from 0.048 to 0.10-0.12 deg, as it does on simulated sweeps that need
// no de-skew: these sweeps behave as already motion-compensated.
TEST(OdometryKitti, AllFramesAgainstOrbSlam3) {
  if (kitti().frames.empty()) GTEST_SKIP() << "kitti_tracking0000 not found";
  const auto e = run_kitti(0, 50, 1, kitti_config());
  report("kitti_tracking0000", e);
  EXPECT_LT(e.rpe_t_m, 0.018);
  EXPECT_LT(e.rpe_r_deg, 0.053);
  EXPECT_LT(e.ate_se3_m, 0.145);
  EXPECT_LT(e.ate_sim3_m, 0.03);
  EXPECT_GT(e.est_path_m / e.path_m, 0.965);
  EXPECT_LT(e.est_path_m / e.path_m, 0.98);
}

// The held-out half (the settings were chosen on frames 0-24), run from its own first frame:
// RPE 1.55 cm / 0.048 deg, ATE 0.069 m (Sim3 0.012 m), path 0.9773 of the reference's.
TEST(OdometryKitti, HeldOutFramesAgainstOrbSlam3) {
  if (kitti().frames.empty()) GTEST_SKIP() << "kitti_tracking0000 not found";
  const auto e = run_kitti(25, 50, 1, kitti_config());
  report("kitti_tracking0000 25-49", e);
  EXPECT_LT(e.rpe_t_m, 0.018);
  EXPECT_LT(e.rpe_r_deg, 0.053);
  EXPECT_LT(e.ate_se3_m, 0.08);
  EXPECT_LT(e.ate_sim3_m, 0.02);
}

// The 0.22 deg elevation correction (IMLS-SLAM's for KITTI's HDL-64E) turns every point up about
// the horizontal axis across its azimuth, range and azimuth kept, and leaves the path's scale:
// 0.9713 of the reference's against 0.9715 without.
TEST(OdometryKitti, ElevationCorrectionTurnsPointsUpAndLeavesTheScale) {
  PointCloud c;
  Point p;
  p.x = 3, p.y = 4, p.z = -1;
  c.points.push_back(p);
  const double a = 0.22 * 3.14159265358979 / 180;
  correct_elevation(c, a);
  const auto& q = c.points[0];
  EXPECT_NEAR(std::hypot(q.x, q.y, q.z), std::sqrt(26.0), 1e-5);
  EXPECT_NEAR(std::atan2(q.y, q.x), std::atan2(4.0, 3.0), 1e-6);
  EXPECT_NEAR(std::atan2(q.z, std::hypot(q.x, q.y)), std::atan2(-1.0, 5.0) + a, 1e-6);
  if (kitti().frames.empty()) GTEST_SKIP() << "kitti_tracking0000 not found";
  OdometryConfig cfg = kitti_config();
  cfg.preprocess.elevation_correction_deg = 0.22;
  const auto e = run_kitti(0, 50, 1, cfg);
  report("kitti_tracking0000, 0.22 deg", e);
  EXPECT_NEAR(e.est_path_m / e.path_m, 0.9715, 0.002);
  EXPECT_LT(e.rpe_t_m, 0.018);
}

/// Height (m) of the sensor above the road ahead: a plane z = a x + b y + c fitted to the points
/// 4-15 m ahead within 2.5 m of the axis and below -1.3 m, twice refitted to those within 5 cm.
double road_height_m(const PointCloud& cloud) {
  std::vector<Eigen::Vector3d> pts;
  for (const auto& p : cloud.points)
    if (p.x > 4 && p.x < 15 && std::abs(p.y) < 2.5 && p.z < -1.3) pts.emplace_back(p.x, p.y, p.z);
  Eigen::Vector3d abc = Eigen::Vector3d::Zero();
  for (int round = 0; round < 3; ++round) {
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    Eigen::Vector3d b = Eigen::Vector3d::Zero();
    for (const auto& q : pts) {
      const Eigen::Vector3d v(q.x(), q.y(), 1.0);
      A += v * v.transpose();
      b += v * q.z();
    }
    abc = A.ldlt().solve(b);
    std::erase_if(pts, [&](const Eigen::Vector3d& q) {
      return std::abs(q.z() - abc.dot(Eigen::Vector3d(q.x(), q.y(), 1.0))) > 0.05;
    });
  }
  return std::abs(abc.z()) / std::sqrt(1 + abc.x() * abc.x() + abc.y() * abc.y());
}

// The sweeps' own scale: the road ahead lies 1.730 m below the sensor on average over the 50
// sweeps (sd 0.041 m), the HDL-64E's mounting height on the KITTI car (1.73 m). Sweeps 3 % short
// would put it at 1.68 m, so the path 2.85 % shorter than the ORB-SLAM3 reference's is not the
// LiDAR's range scale.
TEST(OdometryKitti, RoadLiesAtTheSensorsMountingHeight) {
  if (kitti().frames.empty()) GTEST_SKIP() << "kitti_tracking0000 not found";
  double sum = 0;
  for (const auto& f : kitti().frames) sum += road_height_m(f);
  const double mean = sum / double(kitti().frames.size());
  std::printf("road 4-15 m ahead: %.4f m below the sensor (mean of 50 sweeps)\n", mean);
  EXPECT_NEAR(mean, 1.73, 0.015);
}

TEST(OdometryKitti, EverySecondThirdAndFifthFrameDoNotDiverge) {
  if (kitti().frames.empty()) GTEST_SKIP() << "kitti_tracking0000 not found";
  const auto e2 = run_kitti(0, 50, 2, kitti_config());
  report("kitti_tracking0000 every 2nd", e2);
  EXPECT_LT(e2.rpe_t_m, 0.035);
  EXPECT_LT(e2.ate_m, 0.17);
  const auto e3 = run_kitti(0, 50, 3, kitti_config());
  report("kitti_tracking0000 every 3rd", e3);
  EXPECT_LT(e3.rpe_t_m, 0.045);
  EXPECT_LT(e3.ate_m, 0.17);
  // 1.8 m between frames: the first one is aligned on the coarse map.
  const auto e5 = run_kitti(0, 50, 5, kitti_config());
  report("kitti_tracking0000 every 5th", e5);
  EXPECT_LT(e5.rpe_t_m, 0.07);
  EXPECT_LT(e5.ate_m, 0.17);
}

}  // namespace
}  // namespace fieldlidar::odometry::test
