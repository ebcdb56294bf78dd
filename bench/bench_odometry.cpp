// Per-frame time of the odometry (one core): a simulated VLP-16 greenhouse sweep with IMU and
// wheels, and a real HDL-64E KITTI sweep, each registered against the map of the frames before.

#include <filesystem>
#include <vector>

#include <benchmark/benchmark.h>

#include "fieldlidar/io/cloud_file.hpp"
#include "fieldlidar/odometry/lidar_odometry.hpp"
#include "fieldlidar/sim/lidar_simulator.hpp"
#include "fieldlidar/sim/motion.hpp"
#include "fieldlidar/sim/scenes.hpp"

namespace {

using namespace fieldlidar;

/// Registers frames[0..n-1] once (the map), then times frame n-1's successor repeatedly from
/// the same state.
void run_sequence(benchmark::State& state, const SensorModel& sensor,
                  const std::vector<PointCloud>& frames, const odometry::OdometryConfig& cfg) {
  odometry::LidarOdometry warm(sensor, cfg);
  for (std::size_t i = 0; i + 1 < frames.size(); ++i) warm.register_frame(frames[i]);
  for (auto _ : state) {
    state.PauseTiming();
    odometry::LidarOdometry odo = warm;
    state.ResumeTiming();
    benchmark::DoNotOptimize(odo.register_frame(frames.back()));
  }
  state.counters["points"] = double(frames.back().size());
}

void BM_OdometryGreenhouseVlp16(benchmark::State& state) {
  static const auto frames = [] {
    const auto scene = sim::make_scene(sim::SceneKind::kGreenhouse, 0);
    const auto motion = sim::drive_scene_route(scene, 3.0);
    const sim::LidarSimulator simulator(scene, SensorModel::vlp16());
    std::vector<PointCloud> out;
    for (int i = 0; i < 10; ++i) {
      auto f = simulator.scan(1.0 + 0.1 * i, motion.lidar_pose_fn());
      f.cloud.stamp_s = f.stamp_s;
      out.push_back(std::move(f.cloud));
    }
    return out;
  }();
  run_sequence(state, SensorModel::vlp16(), frames, {});
}
BENCHMARK(BM_OdometryGreenhouseVlp16)->Unit(benchmark::kMillisecond);

void BM_OdometryKittiHdl64(benchmark::State& state) {
  const std::filesystem::path dir =
      std::filesystem::path(FIELDLIDAR_DEFAULT_DATA_DIR) / "kitti_tracking0000" / "velodyne";
  if (!std::filesystem::exists(dir)) {
    state.SkipWithError("kitti_tracking0000 not found");
    return;
  }
  static const auto frames = [&] {
    std::vector<PointCloud> out;
    for (int i = 0; i < 6; ++i) {
      char name[32];
      std::snprintf(name, sizeof name, "%010d.pcd", i);
      out.push_back(io::read_cloud(dir / name));
      out.back().stamp_s = 0.1 * i;
    }
    return out;
  }();
  run_sequence(state, SensorModel::hdl64e(), frames, {});
}
BENCHMARK(BM_OdometryKittiHdl64)->Unit(benchmark::kMillisecond);

}  // namespace
