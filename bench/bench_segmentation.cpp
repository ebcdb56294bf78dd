// Ground segmentation and clustering timings on real frames (one core), with PCL's
// EuclideanClusterExtraction as the side-by-side baseline.
//
// Patchwork++ (its defaults, one core) for reference: ~14 ms on rellis3d/000001.bin, ~27 ms on
// kitti00/000000.bin, ~38 ms on pcd_os128/000000.pcd.

#include <filesystem>
#include <map>
#include <numbers>
#include <string>

#include <benchmark/benchmark.h>

#include "fieldlidar/io/cloud_file.hpp"
#include "fieldlidar/segmentation/segment.hpp"

#if __has_include("fieldlidar/sim/scenes.hpp")
#include "fieldlidar/sim/lidar_simulator.hpp"
#include "fieldlidar/sim/motion.hpp"
#include "fieldlidar/sim/scenes.hpp"
#define FIELDLIDAR_BENCH_WITH_SIM 1
#endif

#ifdef FIELDLIDAR_BENCH_WITH_PCL
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/extract_clusters.h>
#endif

namespace fieldlidar::segmentation {
namespace {

struct Frame {
  PointCloud cloud;
  SensorModel sensor;
  bool ok = false;
};

const Frame& frame(const std::string& name) {
  static std::map<std::string, Frame> cache;
  auto it = cache.find(name);
  if (it != cache.end()) return it->second;
  Frame f;
  const std::filesystem::path dir = FIELDLIDAR_DEFAULT_DATA_DIR;
  if (name == "vlp16-sim") {
#ifdef FIELDLIDAR_BENCH_WITH_SIM
    const sim::Scene scene = sim::make_scene(sim::SceneKind::kLawn, 7);
    const auto motion = sim::drive_scene_route(scene, 2.0);
    f.sensor = SensorModel::vlp16();
    f.cloud = sim::LidarSimulator(scene, f.sensor).scan(1.0, motion.lidar_pose_fn()).cloud;
    f.ok = true;
#endif
  } else if (name == "vlp16-sim-roll30") {
#ifdef FIELDLIDAR_BENCH_WITH_SIM
    // The same sweep from a sensor rolled 30 deg on its mount (handheld, on a slope).
    const sim::Scene scene = sim::make_scene(sim::SceneKind::kLawn, 7);
    const auto motion = sim::drive_scene_route(scene, 2.0);
    const Eigen::Matrix3d roll =
        Eigen::AngleAxisd(30.0 * std::numbers::pi / 180.0, Eigen::Vector3d::UnitX())
            .toRotationMatrix();
    f.sensor = SensorModel::vlp16();
    f.cloud = sim::LidarSimulator(scene, f.sensor)
                  .scan(1.0,
                        [&motion, roll](double t) {
                          Pose T = motion.T_world_lidar(t);
                          T.linear() = T.linear() * roll;
                          return T;
                        })
                  .cloud;
    f.ok = true;
#endif
  } else {
    const std::map<std::string, std::pair<std::string, std::string>> files = {
        {"rellis", {"rellis3d/000001.bin", "os1-64"}},
        {"kitti", {"kitti00/000000.bin", "hdl64e"}},
        {"os128", {"pcd_os128/000000.pcd", "os1-128"}},
        {"topography", {"terrain_als/Topography.las", "hdl64e"}},  // no sensor: grid ground
        {"pine_plot", {"forest_tls/pine_plot.las", "hdl64e"}}};
    const auto& [file, preset] = files.at(name);
    if (std::filesystem::exists(dir / file)) {
      f.cloud = io::read_cloud(dir / file);
      f.sensor = *SensorModel::preset(preset);
      if (name == "rellis") f.sensor.columns = 2048;
      f.ok = true;
    }
  }
  return cache.emplace(name, std::move(f)).first->second;
}

#define REQUIRE_FRAME(f, name)                            \
  const Frame& f = frame(name);                           \
  if (!f.ok) {                                            \
    state.SkipWithError("data for '" name "' is absent"); \
    return;                                               \
  }

void BM_Ground(benchmark::State& state, const char* name, GroundMethod method) {
  const Frame& f = frame(name);
  if (!f.ok) {
    state.SkipWithError("data is absent");
    return;
  }
  GroundConfig cfg;
  cfg.method = method;
  std::size_t ground = 0;
  for (auto _ : state) {
    GroundResult r = segment_ground(f.cloud, f.sensor, cfg);
    ground = r.ground_count;
    benchmark::DoNotOptimize(r.is_ground.data());
  }
  state.counters["points"] = double(f.cloud.size());
  state.counters["ground"] = double(ground);
}
BENCHMARK_CAPTURE(BM_Ground, rellis_robust, "rellis", GroundMethod::kRobust)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Ground, kitti_robust, "kitti", GroundMethod::kRobust)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Ground, os128_robust, "os128", GroundMethod::kRobust)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Ground, vlp16_robust, "vlp16-sim", GroundMethod::kRobust)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Ground, vlp16_roll30_robust, "vlp16-sim-roll30", GroundMethod::kRobust)
    ->Unit(benchmark::kMicrosecond);
// Clouds that are not one sweep: an airborne tile (73k returns over 286 x 286 m, 3 m cells) and a
// terrestrial plot (114k returns over 10 x 10 m, 0.5 m cells).
BENCHMARK_CAPTURE(BM_Ground, topography_grid, "topography", GroundMethod::kGrid)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Ground, pine_plot_grid, "pine_plot", GroundMethod::kGrid)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Ground, rellis_seed000, "rellis", GroundMethod::kSeed000)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Ground, kitti_seed000, "kitti", GroundMethod::kSeed000)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Ground, rellis_seed002, "rellis", GroundMethod::kSeed002)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Ground, kitti_seed002, "kitti", GroundMethod::kSeed002)
    ->Unit(benchmark::kMillisecond);

// What the levelling costs a level sweep: the up estimate alone (the robust ground then runs on
// the cloud as it is).
void BM_EstimateUp(benchmark::State& state, const char* name) {
  const Frame& f = frame(name);
  if (!f.ok) {
    state.SkipWithError("data is absent");
    return;
  }
  for (auto _ : state) {
    UpEstimate up = estimate_up(f.cloud);
    benchmark::DoNotOptimize(up);
  }
  state.counters["tilt_deg"] = estimate_up(f.cloud).tilt_deg;
}
BENCHMARK_CAPTURE(BM_EstimateUp, rellis, "rellis")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_EstimateUp, kitti, "kitti")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_EstimateUp, vlp16, "vlp16-sim")->Unit(benchmark::kMicrosecond);

void BM_RangeImage(benchmark::State& state) {
  REQUIRE_FRAME(f, "kitti");
  for (auto _ : state) {
    RangeImage img = RangeImage::build(f.cloud, f.sensor);
    benchmark::DoNotOptimize(img.cell_point.data());
  }
}
BENCHMARK(BM_RangeImage)->Unit(benchmark::kMillisecond);

// Non-ground points of a frame from the robust ground.
const std::vector<std::uint8_t>& robust_ground(const std::string& name) {
  static std::map<std::string, std::vector<std::uint8_t>> cache;
  auto it = cache.find(name);
  if (it == cache.end())
    it = cache.emplace(name, ground_robust(frame(name).cloud, frame(name).sensor).is_ground).first;
  return it->second;
}
const std::vector<std::uint8_t>& kitti_ground() {
  return robust_ground("kitti");
}

void BM_Euclidean(benchmark::State& state, const char* name,
                  EuclideanClusterConfig::Search search) {
  const Frame& f = frame(name);
  if (!f.ok) {
    state.SkipWithError("data is absent");
    return;
  }
  const auto& skip = robust_ground(name);
  EuclideanClusterConfig cfg;  // 0.5 m
  cfg.min_points = 20;         // as the PCL baseline below
  cfg.search = search;
  std::size_t clusters = 0;
  for (auto _ : state) {
    ClusterResult r = cluster_euclidean(f.cloud, skip, cfg);
    clusters = r.clusters.size();
    benchmark::DoNotOptimize(r.cluster_of_point.data());
  }
  std::size_t n = 0;
  for (auto s : skip) n += !s;
  state.counters["points"] = double(n);
  state.counters["clusters"] = double(clusters);
}
BENCHMARK_CAPTURE(BM_Euclidean, kitti_grid, "kitti", EuclideanClusterConfig::Search::kGrid)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Euclidean, kitti_kdtree, "kitti", EuclideanClusterConfig::Search::kKdTree)
    ->Unit(benchmark::kMillisecond);
// The clustering share of BM_Vlp16Segment/euclidean: the non-ground returns of a VLP-16 sweep.
BENCHMARK_CAPTURE(BM_Euclidean, vlp16_grid, "vlp16-sim", EuclideanClusterConfig::Search::kGrid)
    ->Unit(benchmark::kMicrosecond);

#ifdef FIELDLIDAR_BENCH_WITH_PCL
void BM_PclEuclidean(benchmark::State& state) {
  REQUIRE_FRAME(f, "kitti");
  const auto& skip = kitti_ground();
  pcl::PointCloud<pcl::PointXYZ>::Ptr sub(new pcl::PointCloud<pcl::PointXYZ>);
  for (std::size_t i = 0; i < f.cloud.size(); ++i)
    if (!skip[i] && f.cloud.points[i].is_valid())
      sub->push_back({f.cloud.points[i].x, f.cloud.points[i].y, f.cloud.points[i].z});
  std::size_t clusters = 0;
  for (auto _ : state) {
    // Tree build included, as in cluster_euclidean.
    pcl::search::KdTree<pcl::PointXYZ>::Ptr tree(new pcl::search::KdTree<pcl::PointXYZ>);
    tree->setInputCloud(sub);
    pcl::EuclideanClusterExtraction<pcl::PointXYZ> ec;
    ec.setClusterTolerance(0.5);
    ec.setMinClusterSize(20);
    ec.setMaxClusterSize(std::numeric_limits<int>::max());
    ec.setSearchMethod(tree);
    ec.setInputCloud(sub);
    std::vector<pcl::PointIndices> found;
    ec.extract(found);
    clusters = found.size();
  }
  state.counters["points"] = double(sub->size());
  state.counters["clusters"] = double(clusters);
}
BENCHMARK(BM_PclEuclidean)->Unit(benchmark::kMillisecond)->Iterations(3);
#endif

void BM_RangeImageClusters(benchmark::State& state) {
  REQUIRE_FRAME(f, "kitti");
  const auto& skip = kitti_ground();
  const RangeImage img = RangeImage::build(f.cloud, f.sensor);
  std::size_t clusters = 0;
  for (auto _ : state) {
    ClusterResult r = cluster_range_image(f.cloud, img, skip);
    clusters = r.clusters.size();
    benchmark::DoNotOptimize(r.cluster_of_point.data());
  }
  state.counters["clusters"] = double(clusters);
}
BENCHMARK(BM_RangeImageClusters)->Unit(benchmark::kMillisecond);

// Ground + clusters of a VLP-16 sweep (simulated lawn frame).
void BM_Vlp16Segment(benchmark::State& state, ClusterMethod method) {
  REQUIRE_FRAME(f, "vlp16-sim");
  SegmentConfig cfg;
  cfg.cluster_method = method;
  std::size_t clusters = 0;
  for (auto _ : state) {
    SegmentResult r = segment(f.cloud, f.sensor, cfg);
    clusters = r.clusters.clusters.size();
    benchmark::DoNotOptimize(r.ground.is_ground.data());
  }
  state.counters["points"] = double(f.cloud.size());
  state.counters["clusters"] = double(clusters);
}
BENCHMARK_CAPTURE(BM_Vlp16Segment, euclidean, ClusterMethod::kEuclidean)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Vlp16Segment, range_image, ClusterMethod::kRangeImage)
    ->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace fieldlidar::segmentation
