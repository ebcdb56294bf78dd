// Hybrid A* on the map of a real off-road sweep (RELLIS-3D 000001, OS1-64; the vehicle's own
// returns within 2.3 m dropped, as `traversability --min-range 2.3`): the 32 queries of
// PlanReal.Rellis3dPathsKeepOffLabelledObstacles (from the sensor to rings of 12 and 24 m), time
// per plan on one core (161 x 161 cells of 0.5 m, most of them unknown: planned over).

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <vector>

#include <benchmark/benchmark.h>

#include "fieldlidar/io/cloud_file.hpp"
#include "fieldlidar/planning/hybrid_astar.hpp"
#include "fieldlidar/terrain/traversability.hpp"
#include "planning_timing.hpp"

namespace {

using namespace fieldlidar;
using namespace fieldlidar::planning;
using fieldlidar::bench::percentile;
using fieldlidar::bench::thread_cpu_ms;

void BM_HybridAStarRellis3d(benchmark::State& state) {
  const auto file = std::filesystem::path(FIELDLIDAR_DEFAULT_DATA_DIR) / "rellis3d" / "000001.bin";
  if (!std::filesystem::exists(file)) {
    state.SkipWithError("rellis3d data absent");
    return;
  }
  PointCloud cloud = io::read_cloud(file);
  drop_nearer_than(cloud, 2.3);
  SensorModel sensor = SensorModel::os1_64();
  sensor.columns = 2048;
  const Grid2D map = terrain::map_scan(cloud, sensor, Pose::Identity());
  HybridAStar planner(map, {});
  std::vector<double> ms;
  int planned = 0, queries = 0;
  for (auto _ : state) {
    ms.clear();
    planned = queries = 0;
    for (double radius : {12.0, 24.0})
      for (int k = 0; k < 16; ++k) {
        const double bearing = k * M_PI / 8.0;
        const double t0 = thread_cpu_ms();
        const PlanResult r = planner.plan(
            {0.0, 0.0, 0.0}, {radius * std::cos(bearing), radius * std::sin(bearing), bearing});
        ++queries;
        if (!r.ok()) continue;
        ms.push_back(thread_cpu_ms() - t0);
        ++planned;
      }
  }
  state.counters["queries"] = queries;
  state.counters["planned"] = planned;
  state.counters["cpu_median_ms"] = percentile(ms, 0.5);
  state.counters["cpu_p95_ms"] = percentile(ms, 0.95);
  state.counters["cpu_max_ms"] = percentile(ms, 1.0);
}
BENCHMARK(BM_HybridAStarRellis3d)->Iterations(3)->Unit(benchmark::kMillisecond);

}  // namespace
