// Per-frame time of the odometry (one core): a simulated VLP-16 greenhouse sweep (no IMU or wheel
// stream, so the constant-velocity de-skew runs) and a real HDL-64E KITTI sweep, each registered
// against the map of the frames before.

#include <benchmark/benchmark.h>

#include "odometry_frames.hpp"

namespace {

using namespace fieldlidar;

void BM_OdometryGreenhouseVlp16(benchmark::State& state) {
  bench::run_sequence(state, SensorModel::vlp16(), bench::greenhouse_vlp16_frames(), {});
}
BENCHMARK(BM_OdometryGreenhouseVlp16)->Unit(benchmark::kMillisecond);

void BM_OdometryKittiHdl64(benchmark::State& state) {
  bench::run_sequence(state, SensorModel::hdl64e(), bench::kitti_hdl64_frames(), {});
}
BENCHMARK(BM_OdometryKittiHdl64)->Unit(benchmark::kMillisecond);

}  // namespace
