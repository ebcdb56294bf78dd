// Report (not run by default): the LiDAR-only constant-velocity de-skew on the simulated terrain
// drive, sweeps taken from a fixed pose or while moving, with it and without it, and what the
// velocity it uses is made of: the true motion per sweep, its change from one sweep to the next,
// and the error of the estimated motion. TSEED (23), TFRAMES (300).

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include <gtest/gtest.h>

#include "odometry_eval.hpp"

namespace fieldlidar::odometry::test {
namespace {

struct Rms {
  double t2 = 0, r2 = 0;
  int n = 0;
  void add(const Pose& d) {
    const double a = angle_deg(d.linear());
    t2 += d.translation().squaredNorm(), r2 += a * a, ++n;
  }
  void print(const char* what) const {
    std::printf("  %-30s %.2f cm  %.4f deg\n", what, 100 * std::sqrt(t2 / n), std::sqrt(r2 / n));
  }
};

void velocity_terms(const std::vector<Pose>& truth, const std::vector<Pose>& est) {
  Rms motion, change, error, prediction;
  for (std::size_t k = 2; k < truth.size(); ++k) {
    const Pose now = truth[k - 1].inverse() * truth[k],
               before = truth[k - 2].inverse() * truth[k - 1];
    const Pose estimated = est[k - 2].inverse() * est[k - 1];
    motion.add(now);
    change.add(before.inverse() * now);
    error.add(before.inverse() * estimated);
    prediction.add(estimated.inverse() * now);
  }
  motion.print("true motion per sweep");
  change.print("its change sweep to sweep");
  error.print("error of the estimated motion");
  prediction.print("constant-velocity error");
}

TEST(OdometryDeskewTerrain, DISABLED_Report) {
  const int seed = std::getenv("TSEED") ? std::atoi(std::getenv("TSEED")) : 23;
  const int frames = std::getenv("TFRAMES") ? std::atoi(std::getenv("TFRAMES")) : 300;
  const sim::Scene scene = sim::make_terrain_scene({}, std::uint64_t(seed));
  const SensorModel sensor = SensorModel::vlp16();
  const sim::LidarSimulator lidar(scene, sensor);
  const auto motion = sim::drive_scene_route(scene, 0.5 + 0.1 * frames + 2.0);
  for (const bool moving : {false, true}) {
    std::vector<PointCloud> clouds;
    std::vector<Pose> truth;
    for (int f = 0; f < frames; ++f) {
      const double t = 0.5 + 0.1 * f;
      sim::SimFrame frame =
          moving ? lidar.scan(t, motion.lidar_pose_fn()) : lidar.scan(t, motion.T_world_lidar(t));
      frame.cloud.stamp_s = t;
      clouds.push_back(std::move(frame.cloud));
      truth.push_back(motion.T_world_lidar(t));
    }
    const auto rel = relative_to_first(truth);
    for (const bool deskew : {false, true}) {
      OdometryConfig cfg;
      apply_env(cfg);
      cfg.deskew.enabled = deskew;
      LidarOdometry odo(sensor, cfg);
      std::vector<Pose> est;
      for (const auto& c : clouds) est.push_back(odo.register_frame(c).T_world_lidar);
      const auto e = trajectory_errors(est, rel, 10.0);
      const Pose end = est.back().inverse() * rel.back();
      std::printf(
          "terrain seed %d, sweeps %s, de-skew %s: end %.3f m, ATE %.3f m, RPE %.2f cm / %.3f "
          "deg, drift %.3f %% (10 m)\n",
          seed, moving ? "moving" : "fixed", deskew ? "on" : "off", end.translation().norm(),
          e.ate_m, 100 * e.rpe_t_m, e.rpe_r_deg, e.drift_pct);
      if (deskew) velocity_terms(rel, est);
    }
  }
}

}  // namespace
}  // namespace fieldlidar::odometry::test
