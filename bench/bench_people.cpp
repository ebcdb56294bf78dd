// Detection + tracking per frame (seed 000, steps 2-5): simulated VLP-16 and HDL-64E sweeps of
// the lawn with the operator ahead (ground and clusters included, as the follow loop runs them),
// and real 2D scans.

#include <benchmark/benchmark.h>

#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

#include "fieldlidar/follow/pipeline.hpp"
#include "fieldlidar/io/frame_source.hpp"
#include "fieldlidar/people/legs_2d_pipeline.hpp"
#include "fieldlidar/people/tracker.hpp"
#include "fieldlidar/sim/lidar_simulator.hpp"
#include "fieldlidar/sim/scenes.hpp"

namespace {

using namespace fieldlidar;

struct SimFrames {
  SensorModel sensor;
  std::vector<PointCloud> clouds;
  Pose T;
};

SimFrames make_frames(const SensorModel& s0, int n) {
  const auto scene = sim::make_lawn_scene({}, 0);
  SimFrames f;
  f.sensor = s0;
  f.sensor.mounting_height_m = scene.sensor_height_m();
  const sim::LidarSimulator lidar(scene, f.sensor);
  f.T = make_pose(1, 1, scene.ground_height_at({1, 1}) + scene.sensor_height_m(), 0, 0, 0);
  for (int k = 0; k < n; ++k) f.clouds.push_back(lidar.scan(0.1 * k, f.T).cloud);
  return f;
}

void detect_and_track(benchmark::State& state, const SensorModel& model) {
  static std::map<std::string, SimFrames> cache;
  auto it = cache.find(model.name);
  if (it == cache.end()) it = cache.emplace(model.name, make_frames(model, 20)).first;
  const auto& f = it->second;
  follow::FollowConfig cfg;
  people::PersonTracker tracker;
  std::size_t k = 0, people_found = 0;
  double t = 0;
  for (auto _ : state) {
    const auto& cloud = f.clouds[k++ % f.clouds.size()];
    const auto per = follow::perceive(cloud, f.sensor, f.T, cfg);
    tracker.update(t += 0.1, per.people_m);
    people_found += per.people_m.size();
    benchmark::DoNotOptimize(tracker.tracks().data());
  }
  state.counters["points"] = double(f.clouds[0].size());
  state.counters["people_per_frame"] = double(people_found) / double(state.iterations());
}

void BM_DetectTrack_VLP16(benchmark::State& s) {
  detect_and_track(s, SensorModel::vlp16());
}
void BM_DetectTrack_HDL64E(benchmark::State& s) {
  detect_and_track(s, SensorModel::hdl64e());
}
BENCHMARK(BM_DetectTrack_VLP16)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DetectTrack_HDL64E)->Unit(benchmark::kMillisecond);

/// Legs + tracking alone (clusters given): the seed's part without ground and clustering.
void BM_LegsOnly_VLP16(benchmark::State& state) {
  static const auto f = make_frames(SensorModel::vlp16(), 20);
  follow::FollowConfig cfg;
  std::vector<std::vector<std::vector<std::uint32_t>>> clusters;
  for (const auto& c : f.clouds) {
    const auto g = segmentation::segment_ground(c, f.sensor, cfg.ground);
    const auto cl = segmentation::cluster_euclidean(c, g.is_ground, cfg.clusters);
    auto& v = clusters.emplace_back();
    for (const auto& x : cl.clusters) v.push_back(x.indices);
  }
  auto legs = cfg.legs;
  legs.split_azimuth_gap_rad = 2.5 * f.sensor.horizontal_resolution_rad();
  people::PersonTracker tracker;
  std::size_t k = 0;
  double t = 0;
  for (auto _ : state) {
    const auto i = k++ % f.clouds.size();
    const auto det = people::detect_legs_3d(f.clouds[i], clusters[i], legs);
    std::vector<Eigen::Vector2d> pos;
    for (const auto& p : det.people) pos.push_back(p.position_m);
    tracker.update(t += 0.1, pos);
  }
}
BENCHMARK(BM_LegsOnly_VLP16)->Unit(benchmark::kMicrosecond);

/// The valid returns of every scan of `topic` in `bag`, as the legs CLI reads them.
std::vector<std::vector<Eigen::Vector2d>> read_scans_2d(const std::filesystem::path& bag,
                                                        const std::string& topic) {
  std::vector<std::vector<Eigen::Vector2d>> scans;
  auto src = io::FrameSource::open(bag, {topic, {}});
  while (auto fr = src->next()) scans.push_back(people::scan_points_2d(fr->cloud));
  return scans;
}

void BM_Legs2D_RealScan(benchmark::State& state) {
  const auto bag =
      std::filesystem::path(FIELDLIDAR_DEFAULT_DATA_DIR) / "legs_2d" / "positive_1_extracted.bag";
  if (!std::filesystem::exists(bag)) {
    state.SkipWithError("legs_2d data absent");
    return;
  }
  const auto scans = read_scans_2d(bag, "/training_scan");
  const auto cfg = people::default_2d_legs();
  people::StaticBackground bg;
  people::PersonTracker tracker;
  std::size_t k = 0;
  double t = 0;
  for (auto _ : state) {
    const auto& s = scans[k++ % scans.size()];
    const auto det = people::detect_legs_2d(s, cfg, &bg);
    bg.update(s);
    std::vector<Eigen::Vector2d> pos;
    for (const auto& p : det.people) pos.push_back(p.position_m);
    tracker.update(t += 0.1, pos);
  }
}
BENCHMARK(BM_Legs2D_RealScan)->Unit(benchmark::kMicrosecond);

/// What pipeline_2d times per scan.
enum class Pipeline2DPart {
  kWithMatching,  ///< the whole pipeline, its ego-motion from its own scan matching
  kGivenPoses,    ///< the whole pipeline, the poses given (as by wheel odometry)
  kMatchingOnly,  ///< the scan matching alone
};

/// LegPipeline2D per scan (shipped classifier, ego-motion, leg tracks, joint person tracks and
/// occupancy grids) on the moving robot's scans of negative_2.bag (/right_scan) or of the
/// people-tracking benchmark bag (/scan). With given poses, they are the scan matching's, computed
/// before the timing starts: the pipeline then does what it does beside a robot's odometry.
void pipeline_2d(benchmark::State& state, Pipeline2DPart part,
                 const char* relative_bag = "legs_2d/negative_2.bag",
                 const char* topic = "/right_scan") {
  const auto bag = std::filesystem::path(FIELDLIDAR_DEFAULT_DATA_DIR) / relative_bag;
  // The source tree's config folder, compiled in (__FILE__ is relative under ccache's
  // CCACHE_BASEDIR, so the benchmark ran only from the build folder).
  const auto model =
      std::filesystem::path(FIELDLIDAR_SOURCE_CONFIG_DIR) / "legs_2d_classifier.yaml";
  if (!std::filesystem::exists(bag) || !std::filesystem::exists(model)) {
    state.SkipWithError("legs_2d data or config/legs_2d_classifier.yaml absent");
    return;
  }
  const auto scans = read_scans_2d(bag, topic);
  std::ifstream in(model);
  std::stringstream text;
  text << in.rdbuf();
  people::LegPipeline2DConfig cfg;
  cfg.detector.classifier = std::make_shared<const people::LegClassifier>(
      people::leg_classifier_from_yaml(text.str(), model.string()));
  std::vector<Eigen::Isometry2d> poses;
  if (part == Pipeline2DPart::kGivenPoses) {
    people::ScanOdometry2D matched;
    for (const auto& s : scans) poses.push_back(matched.add(s));
  }
  std::optional<people::LegPipeline2D> pipeline;
  people::ScanOdometry2D odometry;
  std::size_t k = 0, iterations = 0;
  for (auto _ : state) {
    const std::size_t i = k % scans.size();
    if (i == 0) {  // restart at the end of the bag: stamps must not decrease
      pipeline.emplace(cfg);
      odometry = people::ScanOdometry2D();
    }
    const auto& s = scans[i];
    switch (part) {
      case Pipeline2DPart::kMatchingOnly:
        benchmark::DoNotOptimize(odometry.add(s));
        iterations += std::size_t(odometry.last_match().iterations);
        break;
      case Pipeline2DPart::kGivenPoses:
        benchmark::DoNotOptimize(pipeline->process(0.1 * double(i), s, poses[i]));
        break;
      case Pipeline2DPart::kWithMatching:
        benchmark::DoNotOptimize(pipeline->process(0.1 * double(i), s));
        break;
    }
    ++k;
  }
  state.counters["points/scan"] = double(scans.front().size());
  if (part == Pipeline2DPart::kMatchingOnly)
    state.counters["icp_iterations"] = double(iterations) / double(k);
}
constexpr const char* kTrackingBag = "legs_2d_tracking/general_tracking_moving_1.bag";
void BM_LegPipeline2D_RealScan(benchmark::State& s) {
  pipeline_2d(s, Pipeline2DPart::kWithMatching);
}
void BM_LegPipeline2D_RealScanGivenPoses(benchmark::State& s) {
  pipeline_2d(s, Pipeline2DPart::kGivenPoses);
}
void BM_ScanMatching2D_RealScan(benchmark::State& s) {
  pipeline_2d(s, Pipeline2DPart::kMatchingOnly);
}
void BM_LegPipeline2D_TrackingBag(benchmark::State& s) {
  pipeline_2d(s, Pipeline2DPart::kWithMatching, kTrackingBag, "/scan");
}
void BM_LegPipeline2D_TrackingBagGivenPoses(benchmark::State& s) {
  pipeline_2d(s, Pipeline2DPart::kGivenPoses, kTrackingBag, "/scan");
}
void BM_LegPipeline2D_LeftScan(benchmark::State& s) {
  pipeline_2d(s, Pipeline2DPart::kWithMatching, "legs_2d/negative_2.bag", "/left_scan");
}
void BM_LegPipeline2D_RearScan(benchmark::State& s) {
  pipeline_2d(s, Pipeline2DPart::kWithMatching, "legs_2d/negative_2.bag", "/rear_scan");
}
void BM_LegPipeline2D_PositiveBag(benchmark::State& s) {
  pipeline_2d(s, Pipeline2DPart::kWithMatching, "legs_2d/positive_4_extracted.bag",
              "/training_scan");
}
BENCHMARK(BM_LegPipeline2D_RealScan)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_LegPipeline2D_RealScanGivenPoses)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_LegPipeline2D_LeftScan)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_LegPipeline2D_RearScan)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_LegPipeline2D_PositiveBag)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_LegPipeline2D_TrackingBag)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_LegPipeline2D_TrackingBagGivenPoses)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ScanMatching2D_RealScan)->Unit(benchmark::kMicrosecond);

}  // namespace
