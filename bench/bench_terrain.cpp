// The traversability map of one scan: a simulated VLP-16 frame of the off-road scene.
#include <benchmark/benchmark.h>

#include "fieldlidar/sim/lidar_simulator.hpp"
#include "fieldlidar/sim/motion.hpp"
#include "fieldlidar/sim/scenes.hpp"
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
