// The navigate loop's planner map, rebuilt after every sweep (loops::area_grid: the fused map cut
// to the operating area, with the rules for what the sensor cannot see: seen-no-ground, the
// blind disk, trench shadows, drop bands and the blind drops), on the off-road scene after 10 m
// of a VLP-16 drive; one core. Arg: the blind drops off (0) / on (1).
#include <cmath>
#include <vector>

#include <benchmark/benchmark.h>

#include "fieldlidar/loops/navigate.hpp"
#include "fieldlidar/sim/lidar_simulator.hpp"
#include "fieldlidar/sim/motion.hpp"
#include "fieldlidar/sim/scenes.hpp"
#include "fieldlidar/terrain/terrain_map.hpp"

using namespace fieldlidar;

static void BM_NavigatePlannerMap(benchmark::State& state) {
  const sim::Scene scene = sim::make_terrain_scene({}, 11);
  const SensorModel sensor = SensorModel::vlp16();
  const sim::LidarSimulator lidar(scene, sensor);
  const auto motion = sim::drive_scene_route(scene, 12.0);
  loops::NavigateConfig cfg;
  if (state.range(0) == 0) cfg.blind_drop_clear_m = 0.0;
  terrain::TerrainMap map(cfg.fusion);
  Pose T = Pose::Identity();
  for (double t = 1.0; t <= 11.0; t += 0.5) {
    T = motion.T_world_lidar(t);
    map.add_scan(lidar.scan(t, T).cloud, sensor, T);
  }
  const GridGeometry area =
      GridGeometry::covering(scene.min_m(), scene.max_m(), cfg.fusion.layers.cell_m);
  const double mast = scene.sensor_height_m();
  const loops::AreaGridRules rules =
      loops::area_grid_rules(cfg, T, T.translation().head<2>(), mast,
                             mast / std::tan(-sensor.beam_altitudes_rad[0]), scene.max_m(), {});
  std::vector<std::uint8_t> marks;
  for (auto _ : state) {
    const Grid2D grid = loops::area_grid(map, area, rules, marks);
    benchmark::DoNotOptimize(grid.geometry().width);
  }
  state.counters["cells"] = double(area.cell_count());
}
BENCHMARK(BM_NavigatePlannerMap)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
