// Single VLP-16 frames of the simulated off-road scene scored per 0.5 m cell against the
// scene's terrain truth, on the cells the map claims to know.
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "fieldlidar/sim/lidar_simulator.hpp"
#include "fieldlidar/sim/motion.hpp"
#include "fieldlidar/sim/scenes.hpp"
#include "fieldlidar/terrain/traversability.hpp"

using namespace fieldlidar;
using namespace fieldlidar::terrain;

namespace {

struct Score {
  int tp = 0, fp = 0, fn = 0, tn = 0;  ///< impassable is positive
  int known = 0, truth_cells = 0;
  double slope_sq = 0;
  int slope_n = 0;
  double impassable_recall() const { return tp / double(std::max(1, tp + fn)); }
  double impassable_precision() const { return tp / double(std::max(1, tp + fp)); }
  double passable_precision() const { return tn / double(std::max(1, tn + fn)); }
  double passable_recall() const { return tn / double(std::max(1, tn + fp)); }
  double accuracy() const { return (tp + tn) / double(std::max(1, known)); }
  double coverage() const { return known / double(std::max(1, truth_cells)); }
  double slope_rmse() const { return std::sqrt(slope_sq / std::max(1, slope_n)); }
};

/// Cells within `radius_m` of the sensor: the map's claim against the truth.
void score(const Grid2D& map, const Grid2D& truth, const Eigen::Vector2d& sensor, double radius_m,
           Score& s) {
  const auto& g = truth.geometry();
  for (int iy = 0; iy < g.height; ++iy)
    for (int ix = 0; ix < g.width; ++ix) {
      const Eigen::Vector2d c = g.cell_center(ix, iy);
      if ((c - sensor).norm() > radius_m) continue;
      ++s.truth_cells;
      const auto v = map.value_at(layer::kImpassable, c);
      if (!v || std::isnan(*v)) continue;
      ++s.known;
      const bool ours = *v > 0.5f, theirs = truth.at("passable", ix, iy) < 0.5f;
      s.tp += ours && theirs;
      s.fp += ours && !theirs;
      s.fn += !ours && theirs;
      s.tn += !ours && !theirs;
      if (!theirs) {
        const float sl = *map.value_at(layer::kSlopeDeg, c);
        s.slope_sq += std::pow(sl - truth.at("slope_deg", ix, iy), 2);
        ++s.slope_n;
      }
    }
}

Score single_frames(const TraversabilityConfig& config, std::uint64_t seed, int frames,
                    double radius_m) {
  const sim::Scene scene = sim::make_terrain_scene({}, seed);
  const Grid2D truth = scene.terrain_truth({.resolution_m = 0.5});
  const sim::LidarSimulator lidar(scene, SensorModel::vlp16());
  const auto motion = sim::drive_scene_route(scene, 2.0 * frames + 1.0);
  Score s;
  for (int f = 0; f < frames; ++f) {
    const double t = 1.0 + 2.0 * f;
    const Pose T = motion.T_world_lidar(t);
    const sim::SimFrame frame = lidar.scan(t, T);
    const Grid2D map = map_scan(frame.cloud, SensorModel::vlp16(), T, config);
    score(map, truth, T.translation().head<2>(), radius_m, s);
  }
  return s;
}

void print(const char* name, const Score& s) {
  std::printf(
      "%s: impassable recall %.3f precision %.3f, passable precision %.3f recall %.3f, "
      "accuracy %.3f, coverage %.3f (%d known), slope RMSE on passable %.2f deg\n",
      name, s.impassable_recall(), s.impassable_precision(), s.passable_precision(),
      s.passable_recall(), s.accuracy(), s.coverage(), s.known, s.slope_rmse());
}

}  // namespace

// Measured (seeds 11/12, 5 frames each, cells within 15 m): default impassable recall
// 0.73/0.78, passable precision 0.95/0.93, slope RMSE 4.3/4.8 deg, coverage 0.26/0.23; the
// seed's method 0.64/0.71, 0.93/0.91, 6.7/8.8 deg. Nothing was tuned on these seeds.
TEST(TerrainSim, SingleVlp16FramesAgainstTruth) {
  for (std::uint64_t seed : {11u, 12u}) {
    const Score ours = single_frames({}, seed, 5, 15.0);
    const Score seed004 = single_frames(seed004_config(), seed, 5, 15.0);
    print(("default seed " + std::to_string(seed)).c_str(), ours);
    print(("seed004 seed " + std::to_string(seed)).c_str(), seed004);
    EXPECT_GT(ours.impassable_recall(), 0.70);
    EXPECT_GT(ours.impassable_precision(), 0.85);
    EXPECT_GT(ours.passable_precision(), 0.92);
    EXPECT_GT(ours.accuracy(), 0.91);
    EXPECT_GT(ours.coverage(), 0.2);
    EXPECT_LT(ours.slope_rmse(), 5.5);
    EXPECT_GE(ours.impassable_recall(), seed004.impassable_recall());
    EXPECT_LT(ours.slope_rmse(), seed004.slope_rmse());
  }
}
