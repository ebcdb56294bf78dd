// The Eigen LM against Ceres' LM on the same matching problem (LmConfig::solver), one core: the
// time of one solve (one set of correspondences: the first round of the last bench sweep, at a
// constant-velocity prior), and the whole sweep's registration with each solver.

#include <vector>

#include <benchmark/benchmark.h>

#include "fieldlidar/odometry/lm_solver.hpp"
#include "odometry_frames.hpp"

namespace {

using namespace fieldlidar;
using odometry::LmSolver;

struct SolveCase {
  std::vector<odometry::Correspondence> matches;
  Pose prior = Pose::Identity();
};

/// The map of frames[0..n-2]; the last sweep's features matched at the pose the previous
/// motion predicts (the first round of its registration, without de-skew).
SolveCase make_case(const SensorModel& sensor, const std::vector<PointCloud>& frames) {
  SolveCase c;
  if (frames.size() < 3) return c;
  odometry::LidarOdometry warm(sensor);
  std::vector<Pose> poses;
  for (std::size_t i = 0; i + 1 < frames.size(); ++i)
    poses.push_back(warm.register_frame(frames[i]).T_world_lidar);
  const Pose& last = poses.back();
  c.prior = last * (poses[poses.size() - 2].inverse() * last);
  const odometry::OdometryConfig cfg;
  const auto pre = odometry::preprocess(frames.back(), sensor, cfg.preprocess);
  const auto f =
      odometry::extract_features(frames.back(), pre.rings, pre.allowed, pre.ground, cfg.features);
  const Eigen::Matrix3f R = c.prior.linear().cast<float>();
  const Eigen::Vector3f t = c.prior.translation().cast<float>();
  for (int edge = 1; edge >= 0; --edge)
    for (const auto& p : edge ? f.edges : f.planes)
      if (auto m = edge ? warm.map().match_edge(R * p + t) : warm.map().match_plane(R * p + t)) {
        m->point_lidar = p.cast<double>();
        c.matches.push_back(*m);
      }
  return c;
}

void run_solve(benchmark::State& state, const SolveCase& c, LmSolver solver) {
  if (solver == LmSolver::kCeres && !odometry::ceres_available()) {
    state.SkipWithError("built without Ceres (libceres-dev): no ceres solver");
    return;
  }
  if (c.matches.empty()) {
    state.SkipWithError("kitti_tracking0000 not found");
    return;
  }
  odometry::LmConfig lm;
  lm.solver = solver;
  odometry::LmResult r;
  for (auto _ : state) benchmark::DoNotOptimize(r = odometry::solve_lm(c.matches, c.prior, lm));
  state.counters["matches"] = double(c.matches.size());
  state.counters["iterations"] = r.iterations;
}

void BM_LmSolveGreenhouseVlp16(benchmark::State& state, LmSolver solver) {
  static const SolveCase c = make_case(SensorModel::vlp16(), bench::greenhouse_vlp16_frames());
  run_solve(state, c, solver);
}
BENCHMARK_CAPTURE(BM_LmSolveGreenhouseVlp16, eigen_lm, LmSolver::kEigenLm)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_LmSolveGreenhouseVlp16, ceres, LmSolver::kCeres)
    ->Unit(benchmark::kMicrosecond);

void BM_LmSolveKittiHdl64(benchmark::State& state, LmSolver solver) {
  static const SolveCase c = make_case(SensorModel::hdl64e(), bench::kitti_hdl64_frames());
  run_solve(state, c, solver);
}
BENCHMARK_CAPTURE(BM_LmSolveKittiHdl64, eigen_lm, LmSolver::kEigenLm)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_LmSolveKittiHdl64, ceres, LmSolver::kCeres)->Unit(benchmark::kMicrosecond);

/// The whole sweep with Ceres' LM (BM_OdometryGreenhouseVlp16 / BM_OdometryKittiHdl64: Eigen).
void run_frame_ceres(benchmark::State& state, const SensorModel& sensor,
                     const std::vector<PointCloud>& frames) {
  if (!odometry::ceres_available()) {
    state.SkipWithError("built without Ceres (libceres-dev): no ceres solver");
    return;
  }
  odometry::OdometryConfig cfg;
  cfg.lm.solver = LmSolver::kCeres;
  bench::run_sequence(state, sensor, frames, cfg);
}

void BM_OdometryGreenhouseVlp16Ceres(benchmark::State& state) {
  run_frame_ceres(state, SensorModel::vlp16(), bench::greenhouse_vlp16_frames());
}
BENCHMARK(BM_OdometryGreenhouseVlp16Ceres)->Unit(benchmark::kMillisecond);

void BM_OdometryKittiHdl64Ceres(benchmark::State& state) {
  run_frame_ceres(state, SensorModel::hdl64e(), bench::kitti_hdl64_frames());
}
BENCHMARK(BM_OdometryKittiHdl64Ceres)->Unit(benchmark::kMillisecond);

}  // namespace
