// The whole follow loop per frame: simulated VLP-16 sweep -> odometry -> de-skew -> ground ->
// clusters -> legs -> tracker -> controller -> boundary (the scan itself is timed separately).

#include <benchmark/benchmark.h>

#include "fieldlidar/follow/pipeline.hpp"
#include "fieldlidar/loops/closed_loop.hpp"
#include "fieldlidar/sim/lidar_simulator.hpp"

namespace {

using namespace fieldlidar;

/// A 10 s closed-loop run per iteration (100 frames, simulation included), reported per frame;
/// the mower's pose from the odometry (arg 0) or the truth (arg 1).
void BM_ClosedLoop_10s(benchmark::State& state) {
  static const auto scene = sim::make_lawn_scene({}, 0);
  loops::ClosedLoopConfig cfg;
  cfg.max_time_s = 10.0;
  cfg.pose_source = state.range(0) == 0 ? loops::PoseSource::kOdometry : loops::PoseSource::kTruth;
  double perception_ms = 0, odometry_ms = 0;
  std::size_t frames = 0;
  for (auto _ : state) {
    const auto r = loops::run_closed_loop(scene, SensorModel::vlp16(), cfg);
    perception_ms += r.mean_perception_ms * double(r.rows.size());
    odometry_ms += r.mean_odometry_ms * double(r.rows.size());
    frames += r.rows.size();
  }
  state.SetLabel(loops::to_string(cfg.pose_source) + " poses");
  state.counters["frames"] =
      benchmark::Counter(double(frames), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["pipeline_ms_per_frame"] = perception_ms / double(frames);
  state.counters["odometry_ms_per_frame"] = odometry_ms / double(frames);
}
BENCHMARK(BM_ClosedLoop_10s)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->Iterations(2);

/// FollowPipeline::step alone on pre-simulated frames (the mower standing, operator walking off).
void BM_PipelineStep_VLP16(benchmark::State& state) {
  static const auto scene = sim::make_lawn_scene({}, 0);
  SensorModel sensor = SensorModel::vlp16();
  sensor.mounting_height_m = scene.sensor_height_m();
  static const sim::LidarSimulator lidar(scene, sensor);
  const Pose T = make_pose(1, 1, scene.ground_height_at({1, 1}) + 0.45, 0, 0, 0);
  std::vector<PointCloud> clouds;
  for (int k = 0; k < 20; ++k) clouds.push_back(lidar.scan(0.1 * k, T).cloud);
  follow::FollowPipeline pipeline(sensor, follow::FollowConfig{});
  const follow::Pose2 mower{1, 1, 0};
  std::size_t k = 0;
  double t = 0;
  for (auto _ : state) {
    const auto out = pipeline.step(clouds[k++ % clouds.size()], T, mower, t += 0.1, 0.1);
    benchmark::DoNotOptimize(out.control.command.v_m_s);
  }
}
BENCHMARK(BM_PipelineStep_VLP16)->Unit(benchmark::kMillisecond);

void BM_SimulatedScan_VLP16(benchmark::State& state) {
  static const auto scene = sim::make_lawn_scene({}, 0);
  static const sim::LidarSimulator lidar(scene, SensorModel::vlp16());
  const Pose T = make_pose(1, 1, 0.45, 0, 0, 0);
  double t = 0;
  for (auto _ : state) benchmark::DoNotOptimize(lidar.scan(t += 0.1, T).cloud.size());
}
BENCHMARK(BM_SimulatedScan_VLP16)->Unit(benchmark::kMillisecond);

}  // namespace
