// The map fused over a whole simulated drive (VLP-16; a scan every 0.5 s, or every sweep de-skewed
// and placed by the true poses or the lidar odometry) scored per 0.5 m cell against the terrain
// truth, and people walking across the route leaving no ghost obstacle.
#include <chrono>
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "fieldlidar/odometry/lidar_odometry.hpp"
#include "fieldlidar/sim/lidar_simulator.hpp"
#include "fieldlidar/sim/motion.hpp"
#include "fieldlidar/sim/scenes.hpp"
#include "fieldlidar/terrain/terrain_map.hpp"
#include "terrain_score.hpp"

using namespace fieldlidar;
using namespace fieldlidar::terrain;
using terrain::test::Score;

namespace {

struct DriveResult {
  Score score;
  Grid2D global;
  int ghost_cells = 0, walker_cells = 0;  ///< truth-passable cells a person walked over
  double ms_per_scan = 0;
};

/// People crossing the route once (at x = 18 m and 36 m, while the robot comes near), then
/// standing off the route.
void add_crossing_walkers(sim::Scene& scene) {
  const double y = scene.robot_route().front().y();
  for (int i = 0; i < 2; ++i) {
    sim::WalkerConfig w;
    w.id = std::uint16_t(i + 1);
    const double x = 18.0 + 18.0 * i;
    w.path_m = {{x, y - 8.0}, {x + 1.0, y + 8.0}};
    w.speed = {{0.0, 0.0}, {4.0 + 14.0 * i, 1.3}};
    scene.add_walker(sim::Walker(w));
  }
}

/// `without`: the same drive's map with nobody walking (its obstacles are no ghosts).
DriveResult drive(const FusionConfig& config, std::uint64_t seed, bool walkers, double every_s,
                  const Grid2D* without = nullptr) {
  sim::Scene scene = sim::make_terrain_scene({}, seed);
  if (walkers) add_crossing_walkers(scene);
  const Grid2D truth = scene.terrain_truth({.resolution_m = 0.5});
  const sim::LidarSimulator lidar(scene, SensorModel::vlp16());
  const auto motion = sim::drive_scene_route(scene, 60.0);
  TerrainMap map(config);
  std::vector<Eigen::Vector2d> path;
  DriveResult r;
  double ms = 0;
  int n = 0;
  for (double t = 0.5; t < 58.0; t += every_s, ++n) {
    const Pose T = motion.T_world_lidar(t);
    const sim::SimFrame frame = lidar.scan(t, T);
    const auto t0 = std::chrono::steady_clock::now();
    map.add_scan(frame.cloud, SensorModel::vlp16(), T);
    ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    path.push_back(T.translation().head<2>());
  }
  r.ms_per_scan = ms / n;
  r.global = map.global_map();
  const Grid2D& global = r.global;
  terrain::test::score(
      global, truth,
      [&](const Eigen::Vector2d& c) {
        for (const auto& p : path)
          if ((c - p).norm() < 15.0) return true;
        return false;
      },
      r.score);
  if (walkers) {
    const auto& g = truth.geometry();
    for (const auto& w : scene.walkers()) {
      Eigen::Vector2d end, dir;
      w.path_point(w.arc_length_at(1e9), end, dir);
      const auto& a = w.config().path_m[0];
      const auto& b = w.config().path_m[1];
      for (int iy = 0; iy < g.height; ++iy)
        for (int ix = 0; ix < g.width; ++ix) {
          const Eigen::Vector2d c = g.cell_center(ix, iy);
          const Eigen::Vector2d ab = b - a;
          const double u = std::clamp((c - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
          if ((a + u * ab - c).norm() > 0.5 || (c - end).norm() < 1.5) continue;
          if (truth.at("passable", ix, iy) < 0.5f) continue;
          if (without && without->value_at(layer::kObstacleProjected, c).value_or(0.f) > 0.5f)
            continue;
          const auto v = global.value_at(layer::kObstacleProjected, c);
          if (!v || std::isnan(*v)) continue;
          ++r.walker_cells;
          r.ghost_cells += *v > 0.5f;
        }
    }
  }
  return r;
}

struct SweepRun {
  Score true_poses, odometry;
  double odometry_max_error_m = 0;
};

/// A sweep taken while the robot moved from T to T_next (the next sweep's start, dt_s later),
/// re-projected onto its start pose at constant velocity (odometry::deskew).
PointCloud deskewed(const PointCloud& sweep, const Pose& T, const Pose& T_next, double dt_s) {
  const auto motion = odometry::SweepMotion::constant_velocity(T.inverse() * T_next, dt_s);
  return odometry::deskew(sweep, odometry::point_times(sweep, {}), motion);
}

/// Every sweep (10 Hz) of a whole drive, each taken while the robot moves (0.15 m and
/// up to 0.6 deg per sweep, skewed as a real sensor's), fused one sweep late, de-skewed at the
/// constant velocity between its pose and the next sweep's, into two maps: one placed by the true
/// poses, one by the lidar odometry (seed 002). The odometry starts at the true first pose (as a
/// gravity and heading reference would start it), so both maps are scored in the world frame; its
/// own de-skew is off. Chosen on the tuned seeds 21/22 (first 30 s; recall with true / odometry
/// poses): de-skewed by the next pose 0.976/0.988 and 0.977/0.986; by the previous sweep's motion
/// 0.979/0.989 and 0.976/0.986 (0.963/0.981 with the odometry de-skewing too); raw sweeps
/// 0.974/0.985 with true poses. The next pose is the sweep's own motion; the previous lags it.
SweepRun every_sweep(std::uint64_t seed) {
  const sim::Scene scene = sim::make_terrain_scene({}, seed);
  const Grid2D truth = scene.terrain_truth({.resolution_m = 0.5});
  const SensorModel sensor = SensorModel::vlp16();
  const sim::LidarSimulator lidar(scene, sensor);
  const auto motion = sim::drive_scene_route(scene, 60.0);
  odometry::OdometryConfig ocfg;
  ocfg.deskew.enabled = false;
  odometry::LidarOdometry odo(sensor, ocfg);
  TerrainMap placed_by_odometry, placed_by_truth;
  std::vector<Eigen::Vector2d> path;
  Pose T_world_first = Pose::Identity(), T_previous = Pose::Identity(),
       T_previous_odo = Pose::Identity();
  PointCloud previous;
  SweepRun r;
  for (int f = 0; f <= 575; ++f) {
    const double t = 0.5 + 0.1 * f;
    const Pose T = motion.T_world_lidar(t);
    const sim::SimFrame frame = lidar.scan(t, motion.lidar_pose_fn());  // moving during the sweep
    if (f == 0) T_world_first = T;
    const Pose T_odo = T_world_first * odo.register_frame(frame.cloud).T_world_lidar;
    if (f > 0) {  // the previous sweep, now that the pose at its end is known
      placed_by_odometry.add_scan(deskewed(previous, T_previous_odo, T_odo, 0.1), sensor,
                                  T_previous_odo);
      placed_by_truth.add_scan(deskewed(previous, T_previous, T, 0.1), sensor, T_previous);
      path.push_back(T_previous.translation().head<2>());
      r.odometry_max_error_m = std::max(
          r.odometry_max_error_m, (T_previous_odo.inverse() * T_previous).translation().norm());
    }
    previous = frame.cloud;
    T_previous = T;
    T_previous_odo = T_odo;
  }
  const auto near_path = [&](const Eigen::Vector2d& c) {
    for (const auto& p : path)
      if ((c - p).norm() < 15.0) return true;
    return false;
  };
  terrain::test::score(placed_by_odometry.global_map(), truth, near_path, r.odometry);
  terrain::test::score(placed_by_truth.global_map(), truth, near_path, r.true_poses);
  return r;
}

}  // namespace

// Tuned on seeds 21 and 22 (the halo, the full-window rule, the slope margin, the bump margin,
// the gap bridging's cap were chosen on them); seeds 23, 24 and 25 held out. Measured (scans every
// 0.5 s): impassable recall 0.986/0.996 tuned, 0.982/0.988/0.991 held out (0.972/0.990 and
// 0.972/0.974/0.976 before a bump's rim blocked; 0.967/0.987, 0.972/0.966/0.971 before low rocks
// kept as ground were found as bumps); impassable precision 0.67-0.69; passable precision
// 0.995-0.999; coverage 0.80-0.84. Slope RMSE on the cells both the truth and the map call
// passable (the slopes a planner uses): 0.86-1.08 deg; on every truth-passable cell the map
// knows: 1.13/1.39 tuned, 1.01/1.15/1.25 held out (2.96/4.13 and 3.02/4.24/3.54 with the
// impassable cells' slope from their own plane, which takes in the foot of the rock beside them:
// 19-22 deg there).
TEST(TerrainFusion, WholeDriveAgainstTruth) {
  for (std::uint64_t seed : {21u, 22u, 23u, 24u, 25u}) {
    const DriveResult r = drive({}, seed, false, 0.5);
    terrain::test::print(("fused seed " + std::to_string(seed)).c_str(), r.score);
    std::printf("  %.2f ms wall per scan (shared machine; bench_terrain has the CPU time)\n",
                r.ms_per_scan);
    EXPECT_GE(r.score.impassable_recall(), 0.97) << seed;
    EXPECT_GE(r.score.passable_precision(), 0.99) << seed;
    EXPECT_GT(r.score.impassable_precision(), 0.65) << seed;
    EXPECT_GT(r.score.coverage(), 0.75) << seed;
    EXPECT_LT(r.score.slope_rmse_agreed(), 1.5) << seed;
    EXPECT_LT(r.score.slope_rmse(), 2.0) << seed;
  }
}

// Every sweep (10 Hz) of whole drives, de-skewed, placed by the true poses and by the lidar
// odometry; seeds 23-25 held out. Measured, impassable recall with true / odometry poses: 0.979 /
// 0.985, 0.989 / 0.980, 0.989 / 0.992 (the odometry's largest position error 0.48, 0.65, 0.49 m);
// passable precision 0.994-0.997; slope RMSE on the cells both call passable 0.83-1.07 deg (true
// poses), 1.17-1.46 deg (odometry); on every truth-passable cell the map knows 1.00/1.12/1.44 deg
// with true poses, 1.77/2.26/2.09 with odometry poses (on seeds 21-25, 2.29-3.62 and 6.6-6.9
// before an impassable cell's slope came from the clear ground around it: the ~2 deg target is
// not met with odometry poses on seeds 24/25). Recall on tuned seeds 21/22: 0.989 / 0.987,
// 0.992 / 0.993; seeds 26/27, never used before: 0.998 / 0.998, 0.995 / 0.992. Seed 23 with true
// poses was 0.970 before a bump's rim blocked (a low rock kept as ground marks its 4 neighbours);
// of its 27 missed cells now, 23 are one rock (0.69 m radius, 0.62 m high) standing in a 0.9 m pit
// with its top level with the pit's rim, seen only from 12-14 m: the map sees one flat surface
// there (the gap between rock and wall is hidden at that grazing angle). Seed 24's 26 misses with
// odometry poses: 20 cells beside a ditch's or pit's edge (the truth takes the steepest point of
// the cell and the height range of its neighbours), 6 a rock's or bush's footprint touches by 2-21
// cm, of which 2 where the odometry is 0.54 m off. The same drives with the sensor noise drawn at
// other sweep times moved recall by about +-0.005.
TEST(TerrainFusion, EverySweepDeskewed) {
  for (std::uint64_t seed : {23u, 24u, 25u}) {
    const SweepRun r = every_sweep(seed);
    terrain::test::print(("every sweep, seed " + std::to_string(seed) + ", true poses").c_str(),
                         r.true_poses);
    terrain::test::print(("every sweep, seed " + std::to_string(seed) + ", odometry").c_str(),
                         r.odometry);
    std::printf("  odometry's largest position error %.3f m\n", r.odometry_max_error_m);
    EXPECT_GE(r.true_poses.impassable_recall(), 0.97) << seed;
    EXPECT_GE(r.odometry.impassable_recall(), 0.97) << seed;
    EXPECT_GE(r.true_poses.passable_precision(), 0.99) << seed;
    EXPECT_GE(r.odometry.passable_precision(), 0.99) << seed;
    EXPECT_GT(r.true_poses.coverage(), 0.75) << seed;
    EXPECT_LT(r.true_poses.slope_rmse_agreed(), 1.5) << seed;
    EXPECT_LT(r.odometry.slope_rmse_agreed(), 2.0) << seed;
    EXPECT_LT(r.true_poses.slope_rmse(), 2.0) << seed;
    EXPECT_LT(r.odometry.slope_rmse(), 2.6) << seed;
  }
}

// Scans every 0.5 s, and every sweep (10 Hz). Before evidence was counted per time, 10 Hz left 5
// of 106 walked-over cells as obstacles: cells the robot saw last while the second walker stood in
// them (the robot already past, behind the hill), and never again.
TEST(TerrainFusion, WalkersLeaveNoGhostObstacle) {
  for (double every_s : {0.5, 0.1}) {
    const DriveResult empty = drive({}, 21, false, every_s);
    const DriveResult r = drive({}, 21, true, every_s, &empty.global);
    std::printf("every %.1f s: ghost cells %d of %d walked-over cells known\n", every_s,
                r.ghost_cells, r.walker_cells);
    EXPECT_GT(r.walker_cells, 20) << every_s;
    EXPECT_EQ(r.ghost_cells, 0) << every_s;
  }
  // Without the decay (ground seen again barely counts) the same walkers do leave obstacles.
  FusionConfig no_decay;
  no_decay.miss_log_odds = -0.01f;
  const DriveResult empty = drive({}, 21, false, 0.5);
  const DriveResult ghosts = drive(no_decay, 21, true, 0.5, &empty.global);
  std::printf("without decay: ghost cells %d of %d\n", ghosts.ghost_cells, ghosts.walker_cells);
  EXPECT_GT(ghosts.ghost_cells, 5);
}
