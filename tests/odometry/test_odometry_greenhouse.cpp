// Accuracy on the simulated greenhouse (VLP-16 with IMU and wheels).

#include <cstdio>
#include <cstdlib>
#include <limits>

#include <gtest/gtest.h>

#include "odometry_eval.hpp"

namespace fieldlidar::odometry::test {
namespace {

int env_int(const char* name, int fallback) {
  const char* v = std::getenv(name);
  return v ? std::atoi(v) : fallback;
}

void report(const char* what, const TrajectoryErrors& e) {
  std::printf("%-34s path %.2f m  drift %.3f %%  RPE %.2f cm / %.3f deg  ATE %.4f m  scale %.5f\n",
              what, e.path_m, e.drift_pct, 100 * e.rpe_t_m, e.rpe_r_deg, e.ate_m, e.scale);
}

// Tuning / report run over many frames: FIELDLIDAR_ODOM_FIRST, FIELDLIDAR_ODOM_FRAMES.
TEST(OdometryGreenhouse, DISABLED_Report) {
  const auto s = simulate_sequence(sim::SceneKind::kGreenhouse, env_int("FIELDLIDAR_ODOM_FIRST", 0),
                                   env_int("FIELDLIDAR_ODOM_FRAMES", 300),
                                   std::uint64_t(env_int("FIELDLIDAR_ODOM_SEED", 0)));
  const auto truth = relative_to_first(s.truth);
  const double seg = 10.0;
  OdometryConfig def;
  apply_env(def);
  std::vector<OdometryResult> res;
  report("default (map, IMU+wheels)", trajectory_errors(run(s, def, true, &res), truth, seg));
  StepTimings t;
  int degenerate = 0;
  double it = 0, inl = 0;
  for (const auto& r : res) {
    t.total_ms += r.timings.total_ms, t.deskew_ms += r.timings.deskew_ms;
    t.preprocess_ms += r.timings.preprocess_ms, t.features_ms += r.timings.features_ms;
    t.match_ms += r.timings.match_ms, t.map_ms += r.timings.map_ms;
    degenerate += r.degenerate, it += r.iterations, inl += r.inliers;
  }
  const double n = double(res.size());
  std::printf(
      "  ms/frame total %.2f (deskew %.2f pre %.2f feat %.2f match %.2f map %.2f), "
      "%.1f LM steps, %.0f matches, %d degenerate frames\n",
      t.total_ms / n, t.deskew_ms / n, t.preprocess_ms / n, t.features_ms / n, t.match_ms / n,
      t.map_ms / n, it / n, inl / n, degenerate);
  report("default without IMU/wheels", trajectory_errors(run(s, def, false), truth, seg));
  if (std::getenv("ONLYDEF")) return;
  OdometryConfig f2f;
  f2f.target = MatchTarget::kPreviousFrame;
  f2f.preprocess.split_ground = true;
  f2f.preprocess.drop_small_clusters = true;
  report("seed (frame to frame, ground+clusters)",
         trajectory_errors(run(s, f2f, true), truth, seg));
  OdometryConfig gc = def;
  gc.preprocess.split_ground = true;
  gc.preprocess.drop_small_clusters = true;
  report("map + seed ground/clusters", trajectory_errors(run(s, gc, true), truth, seg));
}

// 40 frames (4 s) of the first aisle with IMU and wheels: bounds of the greenhouse targets.
TEST(OdometryGreenhouse, ImuWheelsFortyFrames) {
  const auto s = simulate_sequence(sim::SceneKind::kGreenhouse, 0, 40);
  std::vector<OdometryResult> res;
  const auto e =
      trajectory_errors(run(s, OdometryConfig{}, true, &res), relative_to_first(s.truth), 10.0);
  report("greenhouse 40 frames", e);
  EXPECT_LT(e.rpe_t_m, 0.010);
  EXPECT_LT(e.rpe_r_deg, 0.15);  // target 0.08: the first registrations are biased
  EXPECT_LT(e.ate_m, 0.03);
  for (const auto& r : res) EXPECT_EQ(r.motion_source, MotionSource::kImuWheels);
}

// 300 frames (15 m of the first aisle) with IMU and wheels: the forward motion is not shortened.
// Planes and lines fitted to 5 map points (3 cm range noise) made every frame's motion short:
// scale 1.0021 (reference / estimate) here, 1.0025 over the 3000-frame drive. Measured with 10
// points: 1.0003 (8 points: 1.0008).
TEST(OdometryGreenhouse, ForwardMotionIsNotShortened) {
  const auto s = simulate_sequence(sim::SceneKind::kGreenhouse, 0, 300);
  const auto e =
      trajectory_errors(run(s, OdometryConfig{}, true), relative_to_first(s.truth), 10.0, true);
  report("greenhouse 300 frames", e);
  EXPECT_NEAR(e.scale, 1.0, 0.0013);
  EXPECT_LT(e.ate_m, 0.010);  // Sim(3) alignment; 0.0063 m measured
}

// 40 frames without IMU or wheels: the constant-velocity de-skew (registered at mid-sweep) must
// stay bounded; registered at the sweep start it diverged (RPE 45 cm per frame). Measured: RPE
// 0.62 cm with it, 0.50 cm without, over this start from rest (the velocity lags the speed-up);
// over the 3000-frame drive it halves the drift (0.332 % -> 0.145 %).
TEST(OdometryGreenhouse, LidarOnlyConstantVelocityDeskew) {
  const auto s = simulate_sequence(sim::SceneKind::kGreenhouse, 0, 40);
  OdometryConfig off;
  off.deskew.constant_velocity = false;
  const auto truth = relative_to_first(s.truth);
  const auto with = trajectory_errors(run(s, OdometryConfig{}, false), truth, 10.0);
  const auto without = trajectory_errors(run(s, off, false), truth, 10.0);
  report("40 frames, LiDAR only, CV de-skew", with);
  report("40 frames, LiDAR only, no de-skew", without);
  EXPECT_LT(with.rpe_t_m, 0.010);
  EXPECT_LT(with.ate_m, 0.03);
  EXPECT_LT(with.rpe_t_m, 1.5 * without.rpe_t_m);
}

// Localisation: a map from one run, a second run (other noise seed) started 0.4 m and 8 deg
// away from its true pose tracks in it without adding to it.
TEST(OdometryGreenhouse, LocalisesInSavedMap) {
  const auto first = simulate_sequence(sim::SceneKind::kGreenhouse, 0, 20, 0);
  OdometryConfig cfg;
  cfg.deskew.T_base_lidar = first.T_base_lidar;
  LidarOdometry mapper(first.sensor, cfg);
  mapper.add_imu(first.imu);
  mapper.add_wheels(first.wheels);
  for (const auto& f : first.frames) mapper.register_frame(f);
  const PointCloud saved = mapper.map_cloud();
  ASSERT_GT(saved.size(), 1000u);

  const auto second = simulate_sequence(sim::SceneKind::kGreenhouse, 5, 15, 3);
  LidarOdometry loc(second.sensor, cfg);
  const Pose truth0 = first.truth.front().inverse() * second.truth.front();
  const Pose start = truth0 * make_pose(0.4, -0.3, 0, 0, 0, 8 * 3.14159265 / 180);
  loc.set_map(LocalMap::from_cloud(saved, cfg.map), start);
  loc.add_imu(second.imu);
  loc.add_wheels(second.wheels);
  const std::size_t map_size = loc.map().size();
  double se = 0;
  for (std::size_t i = 0; i < second.frames.size(); ++i) {
    const auto r = loc.register_frame(second.frames[i]);
    const Pose truth = first.truth.front().inverse() * second.truth[i];
    const double err = (truth.translation() - r.T_world_lidar.translation()).norm();
    if (i > 0) se += err * err;
  }
  const double rms = std::sqrt(se / double(second.frames.size() - 1));
  std::printf("localisation RMS %.3f m\n", rms);
  EXPECT_LT(rms, 0.05);
  EXPECT_EQ(loc.map().size(), map_size);
}

// Bad input: NaN points, a repeated stamp, a gap, an IMU stream that stops, a featureless frame.
TEST(OdometryGreenhouse, BadInputDegradesGracefully) {
  auto s = simulate_sequence(sim::SceneKind::kGreenhouse, 0, 12);
  OdometryConfig cfg;
  cfg.deskew.T_base_lidar = s.T_base_lidar;
  LidarOdometry odo(s.sensor, cfg);
  std::vector<ImuSample> imu;
  for (const auto& m : s.imu)
    if (m.stamp_s < 0.6) imu.push_back(m);  // the IMU stops after 0.6 s
  odo.add_imu(imu);
  s.frames[3].points[10].x = std::numeric_limits<float>::quiet_NaN();
  std::vector<std::string> warnings;
  for (int i = 0; i < 12; ++i) {
    PointCloud f = s.frames[i];
    if (i == 5) f.stamp_s = s.frames[4].stamp_s;  // repeated stamp (out of order)
    if (i == 8) f.points.resize(20);              // featureless
    const auto r = odo.register_frame(f);
    for (const auto& w : r.warnings) warnings.push_back(w);
    ASSERT_TRUE(r.T_world_lidar.matrix().allFinite());
    if (i == 8) {
      EXPECT_FALSE(r.registered);
    }
  }
  auto seen = [&](const char* text) {
    for (const auto& w : warnings)
      if (w.find(text) != std::string::npos) return true;
    return false;
  };
  EXPECT_TRUE(seen("NaN"));
  EXPECT_TRUE(seen("out of order"));
  EXPECT_TRUE(seen("too few features"));
  EXPECT_TRUE(seen("do not cover"));
  const Pose err = (s.truth.front().inverse() * s.truth.back()).inverse() * odo.pose();
  EXPECT_LT(err.translation().norm(), 0.15);
}

// Per-frame errors of a run (tuning aid): IMU=1 with the motion streams.
TEST(OdometryGreenhouse, DISABLED_PerFrame) {
  const auto s =
      simulate_sequence(sim::SceneKind::kGreenhouse, 0, env_int("FIELDLIDAR_ODOM_FRAMES", 60));
  const auto truth = relative_to_first(s.truth);
  OdometryConfig cfg;
  apply_env(cfg);
  std::vector<OdometryResult> res;
  const auto est = run(s, cfg, std::getenv("IMU") != nullptr, &res);
  for (std::size_t i = 1; i < est.size(); ++i) {
    const Pose e = (truth[i - 1].inverse() * truth[i]).inverse() * (est[i - 1].inverse() * est[i]);
    std::printf("%zu x %.2f y %.2f yaw %.3f  rel err %.2f cm %.3f deg  %zu matches %d it%s\n", i,
                truth[i].translation().x(), truth[i].translation().y(), yaw_of(truth[i]),
                100 * e.translation().norm(), angle_deg(e.linear()), res[i].inliers,
                res[i].iterations, res[i].degenerate ? " degenerate" : "");
  }
}

// De-skew with the true motion, its inverse, or none: the registered relative pose's error.
TEST(OdometryGreenhouse, DISABLED_DeskewOracle) {
  const auto s = simulate_sequence(sim::SceneKind::kGreenhouse, 30, 8);
  for (int mode = 0; mode < 3; ++mode) {
    OdometryConfig cfg;
    cfg.deskew.enabled = false;
    LidarOdometry odo(s.sensor, cfg);
    Pose first;
    double err = 0;
    for (std::size_t i = 0; i + 1 < s.frames.size(); ++i) {
      const Pose delta = s.truth[i].inverse() * s.truth[i + 1];
      const auto motion = SweepMotion::constant_velocity(mode == 1 ? delta.inverse() : delta, 0.1);
      const auto times = point_times(s.frames[i], cfg.deskew);
      const PointCloud c = mode == 2 ? s.frames[i] : deskew(s.frames[i], times, motion);
      const auto r = odo.register_frame(c);
      if (i == 0) first = r.T_world_lidar;
      const Pose truth = s.truth[0].inverse() * s.truth[i];
      err += (truth.translation() - r.T_world_lidar.translation()).norm();
    }
    std::printf("mode %d (0 true, 1 inverse, 2 none): mean error %.2f cm\n", mode,
                100 * err / (s.frames.size() - 1));
  }
}

// How the registered pose moves when a sweep is de-skewed with a scaled true motion.
TEST(OdometryGreenhouse, DISABLED_DeskewResponse) {
  const auto s = simulate_sequence(sim::SceneKind::kGreenhouse, 0, 32);
  OdometryConfig cfg;
  cfg.deskew.T_base_lidar = s.T_base_lidar;
  LidarOdometry mapper(s.sensor, cfg);
  mapper.add_imu(s.imu);
  mapper.add_wheels(s.wheels);
  for (int i = 0; i < 30; ++i) mapper.register_frame(s.frames[i]);
  const int i = 30;
  const Pose truth = s.truth[0].inverse() * s.truth[i];
  const Pose delta = s.truth[i].inverse() * s.truth[i + 1];
  for (double k : {0.0, 1.0, 2.0, -1.0}) {
    OdometryConfig c2 = cfg;
    c2.deskew.enabled = false;
    LidarOdometry odo(s.sensor, c2);
    odo.set_map(mapper.map(), truth);
    const auto motion = SweepMotion::constant_velocity(
        Pose(Eigen::Translation3d(k * delta.translation()) * Eigen::Quaterniond::Identity()), 0.1);
    const PointCloud c = deskew(s.frames[i], point_times(s.frames[i], c2.deskew), motion);
    const auto r = odo.register_frame(c);
    const Eigen::Vector3d d =
        truth.linear().transpose() * (r.T_world_lidar.translation() - truth.translation());
    std::printf("deskew x %.3f m: pose error in lidar frame %.4f %.4f %.4f\n",
                k * delta.translation().x(), d.x(), d.y(), d.z());
  }
}

// A sweep registered against the map of itself: the pose should stay at identity.
TEST(OdometryGreenhouse, DISABLED_SelfRegistration) {
  auto s = simulate_sequence(sim::SceneKind::kGreenhouse, 0, 1, 0);
  OdometryConfig cfg;
  cfg.deskew.enabled = false;
  if (const char* v = std::getenv("THICK")) cfg.map.max_plane_thickness_m = std::atof(v);
  if (const char* v = std::getenv("SPREAD")) cfg.map.min_plane_spread = std::atof(v);
  if (std::getenv("NOEDGE")) cfg.features.edges_per_sector = 0;
  if (std::getenv("NOPLANE")) cfg.features.planes_per_sector = 0;
  LidarOdometry odo(s.sensor, cfg);
  auto f = s.frames[0];
  odo.register_frame(f);
  f.stamp_s += 0.1;
  const auto r = odo.register_frame(f);
  const auto& T = r.T_world_lidar;
  std::printf("t %.4f %.4f %.4f rot %.3f deg, %zu matches\n", T.translation().x(),
              T.translation().y(), T.translation().z(), angle_deg(T.linear()), r.inliers);
}

}  // namespace
}  // namespace fieldlidar::odometry::test
