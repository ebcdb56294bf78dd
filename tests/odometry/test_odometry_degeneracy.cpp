// Degeneracy: a straight corridor (two parallel walls and a floor, no end in range) leaves the
// motion along it unconstrained and must be flagged; a greenhouse aisle with its posts, benches
// and plants must not be.

#include <cstdio>

#include <gtest/gtest.h>

#include "fieldlidar/sim/mesh.hpp"
#include "odometry_eval.hpp"

namespace fieldlidar::odometry::test {
namespace {

std::vector<OdometryResult> run(const SensorModel& sensor, const std::vector<PointCloud>& frames) {
  LidarOdometry odo(sensor);
  std::vector<OdometryResult> out;
  for (const auto& f : frames) out.push_back(odo.register_frame(f));
  return out;
}

TEST(OdometryDegeneracy, CorridorFlaggedAisleNot) {
  // A 400 m corridor, 3 m wide, walls 3 m high: beyond the VLP-16's 100 m either way.
  sim::Scene corridor(
      sim::SceneKind::kCustom,
      sim::HeightField({-200, -3}, {200, 3}, 1.0, [](double, double) { return 0.0; }));
  const auto wall = make_label(LabelClass::kStructure);
  corridor.add_mesh(sim::make_aabb({-200, -1.6, 0}, {200, -1.5, 3}, wall));
  corridor.add_mesh(sim::make_aabb({-200, 1.5, 0}, {200, 1.6, 3}, wall));
  const SensorModel sensor = SensorModel::vlp16();
  const sim::LidarSimulator simulator(corridor, sensor);
  const auto pose = [](double t) { return make_pose(0.5 * t, 0.1, 0.8, 0, 0, 0.02); };
  std::vector<PointCloud> frames;
  for (int i = 0; i < 5; ++i) {
    auto f = simulator.scan(0.1 * i, pose);
    f.cloud.stamp_s = f.stamp_s;
    frames.push_back(std::move(f.cloud));
  }
  const auto corridor_results = run(sensor, frames);
  for (std::size_t i = 1; i < corridor_results.size(); ++i) {
    std::printf("corridor frame %zu: information ratio %.5f\n", i,
                corridor_results[i].information_ratio(0));
    EXPECT_TRUE(corridor_results[i].degenerate) << "corridor frame " << i;
    EXPECT_LT(corridor_results[i].information_ratio(0), 0.0095) << "corridor frame " << i;
  }

  const auto aisle = simulate_sequence(sim::SceneKind::kGreenhouse, 0, 5);
  const auto aisle_results = run(aisle.sensor, aisle.frames);
  for (std::size_t i = 1; i < aisle_results.size(); ++i) {
    std::printf("aisle frame %zu: information ratio %.5f\n", i,
                aisle_results[i].information_ratio(0));
    EXPECT_FALSE(aisle_results[i].degenerate) << "aisle frame " << i;
    EXPECT_GT(aisle_results[i].information_ratio(0), 0.03) << "aisle frame " << i;
  }
}

}  // namespace
}  // namespace fieldlidar::odometry::test
