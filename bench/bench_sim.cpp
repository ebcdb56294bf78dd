// Simulator throughput: full sweeps per second for each scene and sensor, on the calling thread
// (Embree's rtcIntersect1M streams; no threading in the ray casting).

#include <benchmark/benchmark.h>

#include "fieldlidar/sim/lidar_simulator.hpp"
#include "fieldlidar/sim/motion.hpp"
#include "fieldlidar/sim/scenes.hpp"

namespace {

using namespace fieldlidar;

void BM_SimScan(benchmark::State& state, sim::SceneKind kind, SensorModel sensor) {
  const sim::Scene scene = sim::make_scene(kind, 1);
  const auto motion = sim::drive_scene_route(scene, 12.0);
  const sim::LidarSimulator simulator(scene, sensor);
  const auto pose = motion.lidar_pose_fn();
  double t0 = 1.0;
  std::size_t points = 0;
  for (auto _ : state) {
    auto frame = simulator.scan(t0, pose);
    points += frame.cloud.size();
    benchmark::DoNotOptimize(frame.cloud.points.data());
    t0 += sensor.sweep_period_s();
    if (t0 > 10.0) t0 = 1.0;
  }
  state.counters["frames_per_s"] =
      benchmark::Counter(double(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["points_per_frame"] = double(points) / double(state.iterations());
  state.counters["triangles"] = double(scene.mesh().size());
}

BENCHMARK_CAPTURE(BM_SimScan, lawn_vlp16, sim::SceneKind::kLawn, SensorModel::vlp16())
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_SimScan, lawn_hdl64e, sim::SceneKind::kLawn, SensorModel::hdl64e())
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_SimScan, greenhouse_vlp16, sim::SceneKind::kGreenhouse, SensorModel::vlp16())
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_SimScan, greenhouse_hdl64e, sim::SceneKind::kGreenhouse, SensorModel::hdl64e())
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_SimScan, forest_vlp16, sim::SceneKind::kForest, SensorModel::vlp16())
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_SimScan, forest_hdl64e, sim::SceneKind::kForest, SensorModel::hdl64e())
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_SimScan, terrain_vlp16, sim::SceneKind::kTerrain, SensorModel::vlp16())
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_SimScan, terrain_hdl64e, sim::SceneKind::kTerrain, SensorModel::hdl64e())
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_SimScan, forest_tilting2d, sim::SceneKind::kForest, SensorModel::tilting_2d())
    ->Unit(benchmark::kMillisecond);

void BM_SceneBuild(benchmark::State& state, sim::SceneKind kind) {
  for (auto _ : state) {
    const sim::Scene scene = sim::make_scene(kind, 1);
    const sim::LidarSimulator simulator(scene, SensorModel::vlp16());
    benchmark::DoNotOptimize(&simulator);
  }
}
BENCHMARK_CAPTURE(BM_SceneBuild, lawn, sim::SceneKind::kLawn)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_SceneBuild, terrain, sim::SceneKind::kTerrain)->Unit(benchmark::kMillisecond);

}  // namespace
