// Read speed of the file formats on real scans, side by side with PCL's own PCD reader.
// Counter `per_point` is the time per point (s), so formats of different sizes compare directly.
#include <cstdlib>
#include <filesystem>
#include <string>

#include <benchmark/benchmark.h>
#include <pcl/console/print.h>
#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>

#include "fieldlidar/io/kitti_bin.hpp"
#include "fieldlidar/io/las.hpp"
#include "fieldlidar/io/pcd.hpp"
#include "fieldlidar/io/ply.hpp"

namespace fs = std::filesystem;
using namespace fieldlidar;

namespace {

fs::path data(const std::string& relative) {
  const char* env = std::getenv("FIELDLIDAR_DATA_DIR");
  return fs::path(env && *env ? env : FIELDLIDAR_DEFAULT_DATA_DIR) / relative;
}

bool require(benchmark::State& state, const fs::path& path) {
  if (fs::exists(path)) return true;
  state.SkipWithError(("missing " + path.string()).c_str());
  return false;
}

void per_point(benchmark::State& state, std::size_t n) {
  state.counters["points"] = static_cast<double>(n);
  state.counters["per_point"] =
      benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate |
                                                     benchmark::Counter::kInvert);
}

/// A binary (uncompressed) PCD of the KITTI frame, written once, for the binary-body comparison.
const fs::path& kitti_binary_pcd() {
  static const fs::path path = [] {
    const auto p = fs::temp_directory_path() / "fieldlidar_bench_kitti000000.pcd";
    io::write_pcd(p, io::read_kitti_bin(data("kitti00/000000.bin")), {.overwrite = true});
    return p;
  }();
  return path;
}

void BM_KittiBin_124k(benchmark::State& state) {
  const auto path = data("kitti00/000000.bin");
  if (!require(state, path)) return;
  std::size_t n = 0;
  for (auto _ : state) {
    auto cloud = io::read_kitti_bin(path);
    n = cloud.size();
    benchmark::DoNotOptimize(cloud.points.data());
  }
  per_point(state, n);
}
BENCHMARK(BM_KittiBin_124k)->Unit(benchmark::kMillisecond);

void BM_PcdCompressedOs128_Ours(benchmark::State& state) {
  const auto path = data("pcd_os128/000000.pcd");
  if (!require(state, path)) return;
  std::size_t n = 0;
  for (auto _ : state) {
    auto cloud = io::read_pcd(path);
    n = cloud.size();
    benchmark::DoNotOptimize(cloud.points.data());
  }
  per_point(state, n);
}
BENCHMARK(BM_PcdCompressedOs128_Ours)->Unit(benchmark::kMillisecond);

void BM_PcdCompressedOs128_PclLoadPCDFile(benchmark::State& state) {
  const auto path = data("pcd_os128/000000.pcd");
  if (!require(state, path)) return;
  // The os128 file's intensity is uint8, which PointXYZI cannot take: PCL warns on every read.
  pcl::console::setVerbosityLevel(pcl::console::L_ERROR);
  std::size_t n = 0;
  for (auto _ : state) {
    pcl::PointCloud<pcl::PointXYZI> cloud;
    if (pcl::io::loadPCDFile<pcl::PointXYZI>(path.string(), cloud) < 0) {
      state.SkipWithError("PCL could not read the file");
      return;
    }
    n = cloud.size();
    benchmark::DoNotOptimize(cloud.points.data());
  }
  per_point(state, n);
}
BENCHMARK(BM_PcdCompressedOs128_PclLoadPCDFile)->Unit(benchmark::kMillisecond);

void BM_PcdBinaryKitti_Ours(benchmark::State& state) {
  if (!require(state, data("kitti00/000000.bin"))) return;
  const auto& path = kitti_binary_pcd();
  std::size_t n = 0;
  for (auto _ : state) {
    auto cloud = io::read_pcd(path);
    n = cloud.size();
    benchmark::DoNotOptimize(cloud.points.data());
  }
  per_point(state, n);
}
BENCHMARK(BM_PcdBinaryKitti_Ours)->Unit(benchmark::kMillisecond);

void BM_PcdBinaryKitti_PclLoadPCDFile(benchmark::State& state) {
  if (!require(state, data("kitti00/000000.bin"))) return;
  const auto& path = kitti_binary_pcd();
  // The os128 file's intensity is uint8, which PointXYZI cannot take: PCL warns on every read.
  pcl::console::setVerbosityLevel(pcl::console::L_ERROR);
  std::size_t n = 0;
  for (auto _ : state) {
    pcl::PointCloud<pcl::PointXYZI> cloud;
    if (pcl::io::loadPCDFile<pcl::PointXYZI>(path.string(), cloud) < 0) {
      state.SkipWithError("PCL could not read the file");
      return;
    }
    n = cloud.size();
    benchmark::DoNotOptimize(cloud.points.data());
  }
  per_point(state, n);
}
BENCHMARK(BM_PcdBinaryKitti_PclLoadPCDFile)->Unit(benchmark::kMillisecond);

void BM_Las(benchmark::State& state, const char* relative) {
  const auto path = data(relative);
  if (!require(state, path)) return;
  std::size_t n = 0;
  for (auto _ : state) {
    auto las = io::read_las(path);
    n = las.cloud.size();
    benchmark::DoNotOptimize(las.cloud.points.data());
  }
  per_point(state, n);
}
BENCHMARK_CAPTURE(BM_Las, Topography_format1, "terrain_als/Topography.las")
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Las, PinePlot_format0, "forest_tls/pine_plot.las")
    ->Unit(benchmark::kMillisecond);

void BM_PlyBinaryKitti_Ours(benchmark::State& state) {
  if (!require(state, data("kitti00/000000.bin"))) return;
  static const fs::path path = [] {
    const auto p = fs::temp_directory_path() / "fieldlidar_bench_kitti000000.ply";
    io::write_ply(p, io::read_kitti_bin(data("kitti00/000000.bin")), {.overwrite = true});
    return p;
  }();
  std::size_t n = 0;
  for (auto _ : state) {
    auto cloud = io::read_ply(path);
    n = cloud.size();
    benchmark::DoNotOptimize(cloud.points.data());
  }
  per_point(state, n);
}
BENCHMARK(BM_PlyBinaryKitti_Ours)->Unit(benchmark::kMillisecond);

}  // namespace
