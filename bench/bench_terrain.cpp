// The traversability map of one scan: a simulated VLP-16 frame of the off-road scene.
#include <benchmark/benchmark.h>

#include "fieldlidar/odometry/deskew.hpp"
#include "fieldlidar/sim/lidar_simulator.hpp"
#include "fieldlidar/sim/motion.hpp"
#include "fieldlidar/sim/scenes.hpp"
#include "fieldlidar/terrain/terrain_map.hpp"
#include "fieldlidar/terrain/traversability.hpp"

using namespace fieldlidar;

static void BM_TerrainMapVlp16Frame(benchmark::State& state) {
  const sim::Scene scene = sim::make_terrain_scene({}, 11);
  const sim::LidarSimulator lidar(scene, SensorModel::vlp16());
  const auto motion = sim::drive_scene_route(scene, 5.0);
  const Pose T = motion.T_world_lidar(3.0);
  const sim::SimFrame frame = lidar.scan(3.0, T);
  terrain::TraversabilityConfig config;
  config.max_range_m = double(state.range(0));
  for (auto _ : state) {
    const Grid2D map = terrain::map_scan(frame.cloud, SensorModel::vlp16(), T, config);
    benchmark::DoNotOptimize(map.geometry().width);
  }
  state.counters["points"] = double(frame.cloud.size());
}
BENCHMARK(BM_TerrainMapVlp16Frame)->Arg(20)->Arg(40)->Unit(benchmark::kMillisecond);

// One map update of the fused map (ground segmentation included), the map already holding the
// drive so far: a VLP-16 and an OS1-64 sweep of the off-road scene.
static void fuse_frames(benchmark::State& state, const SensorModel& sensor) {
  const sim::Scene scene = sim::make_terrain_scene({}, 11);
  const sim::LidarSimulator lidar(scene, sensor);
  const auto motion = sim::drive_scene_route(scene, 12.0);
  std::vector<sim::SimFrame> frames;
  for (double t = 1.0; t < 11.0; t += 0.5) frames.push_back(lidar.scan(t, motion.T_world_lidar(t)));
  terrain::TerrainMap map;
  std::size_t i = 0;
  double touched = 0, updated = 0;
  for (auto _ : state) {
    const auto& f = frames[i++ % frames.size()];
    const auto u = map.add_scan(f.cloud, sensor, f.T_world_lidar_start);
    touched += double(u.cells_touched);
    updated += double(u.cells_updated);
  }
  state.counters["points"] = double(frames.front().cloud.size());
  state.counters["cells_touched"] = benchmark::Counter(touched, benchmark::Counter::kAvgIterations);
  state.counters["cells_updated"] = benchmark::Counter(updated, benchmark::Counter::kAvgIterations);
}
static void BM_TerrainFuseVlp16(benchmark::State& state) {
  fuse_frames(state, SensorModel::vlp16());
}
static void BM_TerrainFuseOs1_64(benchmark::State& state) {
  fuse_frames(state, SensorModel::os1_64());
}
BENCHMARK(BM_TerrainFuseVlp16)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TerrainFuseOs1_64)->Unit(benchmark::kMillisecond);

// Every sweep (10 Hz) of a moving VLP-16, as `traversability` fuses a sequence: the sweep
// de-skewed at the constant velocity to the next sweep's pose, then the map update.
static void BM_TerrainFuseVlp16SweepDeskewed(benchmark::State& state) {
  const sim::Scene scene = sim::make_terrain_scene({}, 11);
  const SensorModel sensor = SensorModel::vlp16();
  const sim::LidarSimulator lidar(scene, sensor);
  const auto motion = sim::drive_scene_route(scene, 12.0);
  std::vector<sim::SimFrame> frames;
  for (double t = 1.0; t < 3.0; t += 0.1) frames.push_back(lidar.scan(t, motion.lidar_pose_fn()));
  terrain::TerrainMap map;
  std::size_t i = 0;
  for (auto _ : state) {
    const auto& f = frames[i++ % frames.size()];
    const auto sweep = odometry::SweepMotion::constant_velocity(
        f.T_world_lidar_start.inverse() * f.T_world_lidar_end, 0.1);
    const PointCloud cloud = odometry::deskew(f.cloud, odometry::point_times(f.cloud, {}), sweep);
    const auto u = map.add_scan(cloud, sensor, f.T_world_lidar_start);
    benchmark::DoNotOptimize(u.cells_updated);
  }
}
BENCHMARK(BM_TerrainFuseVlp16SweepDeskewed)->Unit(benchmark::kMillisecond);
