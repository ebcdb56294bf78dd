#pragma once
// Pose tracking from trunks over a simulated forest drive (as `simulate --scene forest`): KITTI
// drift, end error, and the trunk map against the scene's trees.
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <vector>

#include "fieldlidar/core/labels.hpp"
#include "fieldlidar/core/trajectory_metrics.hpp"
#include "fieldlidar/forest/tracking.hpp"
#include "fieldlidar/odometry/lidar_odometry.hpp"
#include "fieldlidar/segmentation/ground.hpp"
#include "fieldlidar/sim/lidar_simulator.hpp"
#include "fieldlidar/sim/motion.hpp"
#include "fieldlidar/sim/scenes.hpp"

namespace fieldlidar::forest::test {

struct DriveResult {
  std::vector<Pose> estimate, reference;
  double drift_pct = 0, deg_per_100m = 0, end_error_m = 0, path_m = 0;
  int map_truth = 0, map_detected = 0, map_matched = 0;
  double map_dbh_sq = 0, map_dbh_sum = 0, map_pos_sq = 0;
  int tracked_frames = 0;
  double map_recall() const { return map_truth ? double(map_matched) / map_truth : 1.0; }
  double map_precision() const { return map_detected ? double(map_matched) / map_detected : 1.0; }
  double map_dbh_rmse() const { return map_matched ? std::sqrt(map_dbh_sq / map_matched) : 0.0; }
  void print(const char* name) const {
    std::printf(
        "%s: path %.1f m, drift %.3f %% %.2f deg/100 m, end error %.3f m, tracked %d/%zu; map: "
        "truth %d detected %d matched %d recall %.3f precision %.3f DBH RMSE %.4f m bias %+.4f m "
        "position RMSE %.4f m\n",
        name, path_m, drift_pct, deg_per_100m, end_error_m, tracked_frames, estimate.size(),
        map_truth, map_detected, map_matched, map_recall(), map_precision(), map_dbh_rmse(),
        map_matched ? map_dbh_sum / map_matched : 0.0,
        map_matched ? std::sqrt(map_pos_sq / map_matched) : 0.0);
  }
};

/// `frames` sweeps of forest `seed` (noise seed seed + 1, as simulate does); with_odometry: the
/// seed 002 odometry gives the prior motion of each scan and the trunks correct it.
inline DriveResult run_drive(std::uint64_t seed, const SensorModel& sensor, int frames,
                             bool with_odometry, const TrackerConfig& config = {}) {
  const sim::Scene scene = sim::make_forest_scene({}, seed);
  const double period = sensor.sweep_period_s();
  const auto motion = sim::drive_scene_route(scene, frames * period + 1.0);
  sim::SimConfig sc;
  sc.seed = seed + 1;
  const sim::LidarSimulator simulator(scene, sensor, sc);
  TrunkTracker tracker(config);
  std::optional<odometry::LidarOdometry> odo;
  if (with_odometry) odo.emplace(sensor);
  DriveResult d;
  Pose T0 = Pose::Identity(), odo_prev = Pose::Identity();
  std::map<std::uint16_t, int> hits;
  for (int f = 0; f < frames; ++f) {
    const auto frame = simulator.scan(f * period, motion.lidar_pose_fn());
    if (f == 0) T0 = frame.T_world_lidar_start;
    d.reference.push_back(T0.inverse() * frame.T_world_lidar_start);
    for (auto l : frame.cloud.labels)
      if (label_class(l) == LabelClass::kTrunk) ++hits[label_instance(l)];
    const auto ground = segmentation::segment_ground(frame.cloud, sensor);
    std::optional<Pose> prior;
    if (odo) {
      const Pose p = odo->register_frame(frame.cloud).T_world_lidar;
      if (f > 0) prior = odo_prev.inverse() * p;
      odo_prev = p;
    }
    const auto r = tracker.track(frame.cloud, ground.is_ground, prior);
    d.tracked_frames += r.tracked;
    if (std::getenv("FOREST_TRACE"))
      std::printf("f %d trees %zu matched %zu tracked %d t %.3f %.3f %.3f ref %.3f %.3f %.3f\n", f,
                  r.trees, r.matched, r.tracked, r.T_world_lidar.translation().x(),
                  r.T_world_lidar.translation().y(), r.T_world_lidar.translation().z(),
                  d.reference.back().translation().x(), d.reference.back().translation().y(),
                  d.reference.back().translation().z());
    d.estimate.push_back(r.T_world_lidar);
  }
  if (std::getenv("FOREST_TRACE")) {
    const Eigen::Matrix3d dR = d.reference.back().linear().transpose() * d.estimate.back().linear();
    const Eigen::Vector3d e = dR.eulerAngles(2, 1, 0) * 180 / M_PI;
    std::printf("end rotation error (deg, zyx): %.2f %.2f %.2f\n", e.x(), e.y(), e.z());
  }
  const auto path = cumulative_path_m(d.reference);
  d.path_m = path.back();
  const auto drift = kitti_drift(d.estimate, d.reference, {10, 12, 14, 16, 18, 20});
  d.drift_pct = drift.translation_pct;
  d.deg_per_100m = drift.rotation_deg_per_m * 100;
  d.end_error_m = (d.estimate.back().translation() - d.reference.back().translation()).norm();
  // Trunk map: trees whose stem at 1.3 m passed within 10 m of the path, with >= 50 returns over
  // the drive (not hidden all the way), against the map trunks reported (seen in 5 scans or more).
  struct Truth {
    Eigen::Vector3d p;
    double dbh;
    bool scored, used = false;
  };
  std::vector<Truth> truth;
  auto path_distance = [&](const Eigen::Vector3d& p) {
    double best = 1e30;
    for (const auto& T : d.reference) best = std::min(best, (T.translation() - p).head<2>().norm());
    return best;
  };
  for (const auto& t : scene.trunks()) {
    const Eigen::Vector3d p = T0.inverse() * (t.base_m + t.axis * (1.3 / t.axis.z()));
    const double dist = path_distance(p);
    if (dist > 12.0) continue;
    truth.push_back({p, t.dbh_m, dist <= 10.0 && hits[t.id] >= 50});
    d.map_truth += truth.back().scored;
  }
  for (const auto& m : tracker.map_trees()) {
    const Eigen::Vector3d p = m.at_height(1.3);
    if (path_distance(p) > 10.5) continue;
    Truth* best = nullptr;
    double bd = 0.3;
    for (auto& t : truth)
      if (!t.used && (t.p - p).head<2>().norm() < bd) {
        bd = (t.p - p).head<2>().norm();
        best = &t;
      }
    if (best && !best->scored) {
      best->used = true;
      continue;
    }
    ++d.map_detected;
    if (std::getenv("FOREST_TRACE")) {
      double nearest = 1e30;
      for (const auto& t : truth) nearest = std::min(nearest, (t.p - p).head<2>().norm());
      std::printf(
          "  map trunk %u at (%.2f, %.2f) obs %zu dbh %.3f (true %.3f) arc %.0f nearest truth "
          "%.3f m%s\n",
          m.id, p.x(), p.y(), m.observations, m.dbh_m, best ? best->dbh : 0.0, m.arc_deg, nearest,
          best ? "" : "  (unmatched)");
    }
    if (!best) continue;
    best->used = true;
    ++d.map_matched;
    d.map_dbh_sq += std::pow(m.dbh_m - best->dbh, 2);
    d.map_dbh_sum += m.dbh_m - best->dbh;
    d.map_pos_sq += bd * bd;
  }
  return d;
}

}  // namespace fieldlidar::forest::test
