// 3D leg and person detection (seed 000, steps 1-3: ground, leg-band clusters, leg arcs on
// several rings, pairs) per real HDL-64E sweep: kitti_tracking0000, frames 0-9 (~123k points,
// rings estimated once before timing, as eval-people3d does).

#include <benchmark/benchmark.h>

#include <filesystem>
#include <vector>

#include "fieldlidar/follow/pipeline.hpp"
#include "fieldlidar/follow/replay.hpp"
#include "fieldlidar/io/frame_source.hpp"
#include "fieldlidar/people/leg_detector.hpp"

namespace {

using namespace fieldlidar;

const std::vector<PointCloud>& kitti_frames(const SensorModel& sensor) {
  static std::vector<PointCloud> frames = [&] {
    std::vector<PointCloud> out;
    const auto dir =
        std::filesystem::path(FIELDLIDAR_DEFAULT_DATA_DIR) / "kitti_tracking0000" / "velodyne";
    if (!std::filesystem::exists(dir)) return out;
    auto src = io::FrameSource::open(dir);
    while (auto f = src->next()) {
      if (out.size() == 10) break;
      follow::ensure_rings(f->cloud, sensor);
      out.push_back(std::move(f->cloud));
    }
    return out;
  }();
  return frames;
}

void BM_DetectPeople3D_KittiHDL64E(benchmark::State& state) {
  const SensorModel sensor = *SensorModel::preset("hdl64e");
  const auto& frames = kitti_frames(sensor);
  if (frames.empty()) {
    state.SkipWithError("kitti_tracking0000 absent");
    return;
  }
  const follow::FollowConfig cfg;
  std::size_t k = 0, people = 0;
  for (auto _ : state) {
    const auto& cloud = frames[k++ % frames.size()];
    double h = 0;
    const auto clusters = follow::leg_band_clusters(cloud, sensor, cfg, &h);
    const auto det = follow::detect_people_3d(cloud, clusters, sensor, h, cfg);
    people += det.people.size();
    benchmark::DoNotOptimize(det.legs.data());
  }
  state.counters["persons_per_frame"] = double(people) / double(state.iterations());
}
BENCHMARK(BM_DetectPeople3D_KittiHDL64E)->Unit(benchmark::kMillisecond);

}  // namespace
