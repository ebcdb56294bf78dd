// The map fused over a whole simulated drive (VLP-16, true poses) scored per 0.5 m cell against
// the terrain truth, and people walking across the route leaving no ghost obstacle.
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

}  // namespace

// Tuned on seeds 21 and 22 (the halo, the full-window rule, the slope margin, the bump margin,
// the gap bridging's cap were chosen on them); seeds 23, 24 and 25 held out. Measured (scans every
// 0.5 s): impassable recall 0.972/0.990 tuned, 0.972/0.974/0.976 held out (0.967/0.987,
// 0.972/0.966/0.971 before low rocks kept as ground were found as bumps); impassable precision
// 0.67-0.72; passable precision 0.992-0.997; coverage 0.79-0.84. Slope RMSE is on the cells both
// the truth and the map call passable (the slopes a planner uses).
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
  }
}

// The same map placed by the lidar odometry (seed 002) instead of the true poses: every sweep of
// the first 30 s at 10 Hz, the map in the first scan's frame. Seed 23 (held out). The sweeps are
// taken while the robot moves (15 cm and 0.56 deg per sweep), as a real sensor takes them: swept
// from a fixed pose they had no skew, and the odometry's constant-velocity de-skew could only add
// one (end error 0.305 m with it, 0.152 m without).
TEST(TerrainFusion, PlacedByLidarOdometry) {
  const sim::Scene scene = sim::make_terrain_scene({}, 23);
  const Grid2D truth = scene.terrain_truth({.resolution_m = 0.5});
  const SensorModel sensor = SensorModel::vlp16();
  const sim::LidarSimulator lidar(scene, sensor);
  const auto motion = sim::drive_scene_route(scene, 32.0);
  odometry::LidarOdometry odo(sensor);
  TerrainMap map, truth_placed;
  std::vector<Eigen::Vector2d> path;
  Pose T_world_first = Pose::Identity(), last_error = Pose::Identity();
  for (int f = 0; f < 300; ++f) {
    const double t = 0.5 + 0.1 * f;
    const Pose T = motion.T_world_lidar(t);
    sim::SimFrame frame = lidar.scan(t, motion.lidar_pose_fn());  // moving during the sweep
    frame.cloud.stamp_s = t;
    if (f == 0) T_world_first = T;
    const Pose T_odo = odo.register_frame(frame.cloud).T_world_lidar;
    map.add_scan(frame.cloud, sensor, T_odo);
    truth_placed.add_scan(frame.cloud, sensor, T);
    path.push_back(T.translation().head<2>());
    last_error = (T_world_first * T_odo).inverse() * T;
  }
  const Pose T_map_world = T_world_first.inverse();
  const auto near_path = [&](const Eigen::Vector2d& c) {
    for (const auto& p : path)
      if ((c - p).norm() < 15.0) return true;
    return false;
  };
  Score s, t;
  terrain::test::score(map.global_map(), truth, near_path, s, &T_map_world);
  terrain::test::score(truth_placed.global_map(), truth, near_path, t);
  terrain::test::print("fused seed 23, odometry poses", s);
  terrain::test::print("fused seed 23, true poses", t);
  std::printf("  odometry end error %.3f m over %.1f m\n", last_error.translation().norm(),
              (path.back() - path.front()).norm());
  // Measured: recall 0.950 (true poses 0.956), passable precision 0.987, coverage 0.81, odometry
  // end error 0.197 m. Without the odometry's constant-velocity de-skew: recall 0.969, end error
  // 0.114 m, though its drift over 10 m is 0.57 % against 0.31 % with it: the map fuses the raw
  // (skewed) sweeps, which the poses of an odometry that did not de-skew them likely fit better.
  EXPECT_GE(s.impassable_recall(), 0.94);
  EXPECT_GE(s.passable_precision(), 0.98);
  EXPECT_GT(s.coverage(), 0.6);
}

// Scans every 0.5 s. Scanning every sweep (10 Hz) the same drive leaves 5 of 106 walked-over cells
// as obstacles (measured, not asserted): traced, they are cells the robot saw last, once, while
// the second walker stood in them (1.5 m/s robot already past, behind the hill), and never again.
TEST(TerrainFusion, WalkersLeaveNoGhostObstacle) {
  const DriveResult empty = drive({}, 21, false, 0.5);
  const DriveResult r = drive({}, 21, true, 0.5, &empty.global);
  std::printf("ghost cells %d of %d walked-over cells known\n", r.ghost_cells, r.walker_cells);
  EXPECT_GT(r.walker_cells, 20);
  EXPECT_EQ(r.ghost_cells, 0);
  // Without the decay (ground seen again barely counts) the same walkers do leave obstacles.
  FusionConfig no_decay;
  no_decay.miss_log_odds = -0.01f;
  const DriveResult ghosts = drive(no_decay, 21, true, 0.5, &empty.global);
  std::printf("without decay: ghost cells %d of %d\n", ghosts.ghost_cells, ghosts.walker_cells);
  EXPECT_GT(ghosts.ghost_cells, 5);
}
