// Tree extraction per scan (seed 003, steps 1-3): simulated VLP-16 and OS1-64 sweeps of the forest
// (ground included, as a robot would run it; and extraction alone), and the real pine plot file.

#include <benchmark/benchmark.h>

#include <filesystem>

#include "fieldlidar/forest/tracking.hpp"
#include "fieldlidar/forest/trunks.hpp"
#include "fieldlidar/io/cloud_file.hpp"
#include "fieldlidar/segmentation/ground.hpp"
#include "fieldlidar/sim/lidar_simulator.hpp"
#include "fieldlidar/sim/motion.hpp"
#include "fieldlidar/sim/scenes.hpp"

namespace {

using namespace fieldlidar;

PointCloud forest_sweep(const SensorModel& sensor) {
  const auto scene = sim::make_forest_scene({}, 1);
  const auto motion = sim::drive_scene_route(scene, 10.0);
  return sim::LidarSimulator(scene, sensor).scan(6.0, motion.lidar_pose_fn()(6.0)).cloud;
}

void trees_with_ground(benchmark::State& state, const SensorModel& sensor) {
  const PointCloud cloud = forest_sweep(sensor);
  std::size_t trees = 0;
  for (auto _ : state) {
    const auto ground = segmentation::segment_ground(cloud, sensor);
    trees = forest::extract_trees(cloud, ground.is_ground).trees.size();
    benchmark::DoNotOptimize(trees);
  }
  state.counters["points"] = double(cloud.size());
  state.counters["trees"] = double(trees);
}

void trees_only(benchmark::State& state, const SensorModel& sensor) {
  const PointCloud cloud = forest_sweep(sensor);
  const auto ground = segmentation::segment_ground(cloud, sensor);
  for (auto _ : state)
    benchmark::DoNotOptimize(forest::extract_trees(cloud, ground.is_ground).trees.size());
  state.counters["points"] = double(cloud.size());
}

void plot(benchmark::State& state, const char* file) {
  const auto path = std::filesystem::path(FIELDLIDAR_DEFAULT_DATA_DIR) / file;
  if (!std::filesystem::exists(path)) {
    state.SkipWithError("plot file not found");
    return;
  }
  const PointCloud cloud = io::read_cloud(path);
  for (auto _ : state) {
    const auto ground = segmentation::ground_grid(cloud);
    benchmark::DoNotOptimize(forest::extract_trees(cloud, ground.is_ground).trees.size());
  }
  state.counters["points"] = double(cloud.size());
}

// Tracking on top of extraction: one scan of a drive tracked against the map of the scans before
// it (the time of the track call less extraction alone is the tracking cost).
void tracking(benchmark::State& state) {
  const auto sensor = SensorModel::vlp16();
  const auto scene = sim::make_forest_scene({}, 3);
  const auto motion = sim::drive_scene_route(scene, 5.0);
  const sim::LidarSimulator sim(scene, sensor);
  std::vector<PointCloud> clouds;
  std::vector<std::vector<std::uint8_t>> grounds;
  for (int f = 0; f < 20; ++f) {
    clouds.push_back(sim.scan(0.1 * f, motion.lidar_pose_fn()).cloud);
    grounds.push_back(segmentation::segment_ground(clouds.back(), sensor).is_ground);
  }
  forest::TrunkTracker warm;
  for (int f = 0; f < 19; ++f) warm.track(clouds[f], grounds[f]);
  for (auto _ : state) {
    forest::TrunkTracker tracker = warm;
    benchmark::DoNotOptimize(tracker.track(clouds[19], grounds[19]).matched);
  }
  state.counters["map_trunks"] = double(warm.map().size());
}

BENCHMARK(tracking)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(trees_with_ground, vlp16, SensorModel::vlp16())->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(trees_with_ground, os1_64, SensorModel::os1_64())->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(trees_only, vlp16, SensorModel::vlp16())->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(trees_only, os1_64, SensorModel::os1_64())->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(plot, pine_plot, "forest_tls/pine_plot.las")->Unit(benchmark::kMillisecond);
// 1.5M points: ground grid and trunks (the file read is not timed).
BENCHMARK_CAPTURE(plot, lpine_1_5M, "forest_tls_lpine/LPine1_demo.las")
    ->Unit(benchmark::kMillisecond);

}  // namespace
