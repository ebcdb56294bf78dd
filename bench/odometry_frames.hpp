#pragma once
// The odometry benchmarks' sweeps: a simulated VLP-16 greenhouse drive and the first real HDL-64E
// KITTI tracking sweeps, and the timing of one sweep's registration against the map of the ones
// before.

#include <cstdio>
#include <filesystem>
#include <vector>

#include <benchmark/benchmark.h>

#include "fieldlidar/io/cloud_file.hpp"
#include "fieldlidar/odometry/lidar_odometry.hpp"
#include "fieldlidar/sim/lidar_simulator.hpp"
#include "fieldlidar/sim/motion.hpp"
#include "fieldlidar/sim/scenes.hpp"

namespace fieldlidar::bench {

/// 10 simulated VLP-16 sweeps of the greenhouse route from t = 1 s (no IMU or wheels).
inline const std::vector<PointCloud>& greenhouse_vlp16_frames() {
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
  return frames;
}

/// kitti_tracking0000 sweeps 0-5 (empty when the data folder is absent).
inline const std::vector<PointCloud>& kitti_hdl64_frames() {
  static const auto frames = [] {
    const std::filesystem::path dir =
        std::filesystem::path(FIELDLIDAR_DEFAULT_DATA_DIR) / "kitti_tracking0000" / "velodyne";
    std::vector<PointCloud> out;
    if (!std::filesystem::exists(dir)) return out;
    for (int i = 0; i < 6; ++i) {
      char name[32];
      std::snprintf(name, sizeof name, "%010d.pcd", i);
      out.push_back(io::read_cloud(dir / name));
      out.back().stamp_s = 0.1 * i;
    }
    return out;
  }();
  return frames;
}

/// Registers frames[0..n-2] once (the map), then times frame n-1 repeatedly from the same state.
inline void run_sequence(benchmark::State& state, const SensorModel& sensor,
                         const std::vector<PointCloud>& frames,
                         const odometry::OdometryConfig& cfg) {
  if (frames.empty()) {
    state.SkipWithError("kitti_tracking0000 not found");
    return;
  }
  odometry::LidarOdometry warm(sensor, cfg);
  for (std::size_t i = 0; i + 1 < frames.size(); ++i) warm.register_frame(frames[i]);
  odometry::OdometryResult last;
  for (auto _ : state) {
    state.PauseTiming();
    odometry::LidarOdometry odo = warm;
    state.ResumeTiming();
    last = odo.register_frame(frames.back());
    benchmark::DoNotOptimize(last);
  }
  state.counters["points"] = double(frames.back().size());
  state.counters["features"] = double(last.edge_features + last.plane_features);
  state.counters["lm_steps"] = double(last.iterations);
  state.counters["matches"] = double(last.inliers);
  state.counters["deskew_ms"] = last.timings.deskew_ms;
  state.counters["pre_ms"] = last.timings.preprocess_ms;
  state.counters["feat_ms"] = last.timings.features_ms;
  state.counters["match_ms"] = last.timings.match_ms;
  state.counters["map_ms"] = last.timings.map_ms;
}

}  // namespace fieldlidar::bench
