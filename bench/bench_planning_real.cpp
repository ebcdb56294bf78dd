// Hybrid A* on the map of a real off-road sweep (RELLIS-3D 000001, OS1-64; the vehicle's own
// returns within 2.3 m dropped, as `traversability --min-range 2.3`): the 32 queries of
// PlanReal.Rellis3dPathsKeepOffLabelledObstacles (from the sensor to rings of 12 and 24 m), time
// per plan on one core (161 x 161 cells of 0.5 m, most of them unknown: planned over).

#include <algorithm>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <memory>
#include <span>
#include <vector>

#include <benchmark/benchmark.h>

#include "fieldlidar/io/cloud_file.hpp"
#include "fieldlidar/planning/hybrid_astar.hpp"
#include "fieldlidar/terrain/traversability.hpp"

namespace {

using namespace fieldlidar;
using namespace fieldlidar::planning;

double cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}

void BM_HybridAStarRellis3d(benchmark::State& state) {
  const auto file = std::filesystem::path(FIELDLIDAR_DEFAULT_DATA_DIR) / "rellis3d" / "000001.bin";
  if (!std::filesystem::exists(file)) {
    state.SkipWithError("rellis3d data absent");
    return;
  }
  const PointCloud all = io::read_cloud(file);
  const auto keep = std::make_unique<bool[]>(all.size());
  for (std::size_t i = 0; i < all.size(); ++i)
    keep[i] = all.points[i].is_valid() && all.points[i].xyz().norm() >= 2.3f;
  SensorModel sensor = SensorModel::os1_64();
  sensor.columns = 2048;
  const Grid2D map = terrain::map_scan(select(all, std::span<const bool>(keep.get(), all.size())),
                                       sensor, Pose::Identity());
  HybridAStar planner(map, {});
  std::vector<double> ms;
  int planned = 0, queries = 0;
  for (auto _ : state) {
    ms.clear();
    planned = queries = 0;
    for (double radius : {12.0, 24.0})
      for (int k = 0; k < 16; ++k) {
        const double bearing = k * M_PI / 8.0;
        const double t0 = cpu_ms();
        const PlanResult r = planner.plan(
            {0.0, 0.0, 0.0}, {radius * std::cos(bearing), radius * std::sin(bearing), bearing});
        ++queries;
        if (!r.ok()) continue;
        ms.push_back(cpu_ms() - t0);
        ++planned;
      }
  }
  std::sort(ms.begin(), ms.end());
  state.counters["queries"] = queries;
  state.counters["planned"] = planned;
  if (!ms.empty()) {
    state.counters["cpu_median_ms"] = ms[ms.size() / 2];
    state.counters["cpu_p95_ms"] =
        ms[std::min(ms.size() - 1, std::size_t(0.95 * (ms.size() - 1) + 0.5))];
    state.counters["cpu_max_ms"] = ms.back();
  }
}
BENCHMARK(BM_HybridAStarRellis3d)->Iterations(3)->Unit(benchmark::kMillisecond);

}  // namespace
