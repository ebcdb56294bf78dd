#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/terrain/traversability.hpp"

using namespace fieldlidar;
using namespace fieldlidar::terrain;

namespace {

/// A dense plane z = tan(slope) * x over [0, 10]^2, every 5 cm, all ground, plus extra points.
struct Cloud {
  std::vector<Eigen::Vector3d> pts;
  std::vector<std::uint8_t> ground;
};
Cloud plane(double slope_deg) {
  Cloud c;
  for (double x = 0.025; x < 10; x += 0.05)
    for (double y = 0.025; y < 10; y += 0.05) {
      c.pts.emplace_back(x, y, std::tan(slope_deg * M_PI / 180) * x);
      c.ground.push_back(1);
    }
  return c;
}
GridGeometry square10() {
  return GridGeometry::covering({0, 0}, {10, 10}, 0.5);
}

}  // namespace

TEST(TerrainVoxel, SideFromFootprintAndHeightFromSlope) {
  TraversabilityConfig c;
  EXPECT_NEAR(voxel_side_m(c), 1.5, 1e-12);  // diagonal 1.10 m -> 3 cells of 0.5 m
  EXPECT_NEAR(voxel_height_m(c), 1.5 * std::tan(25 * M_PI / 180), 1e-12);
  c.robot.length_m = -1;
  EXPECT_THROW(voxel_side_m(c), Error);
  c.robot.length_m = 1;
  c.robot.max_slope_deg = 95;
  EXPECT_THROW(voxel_height_m(c), Error);
}

TEST(TerrainVoxel, PlaneSlopesAreMeasuredAndSteepOnesBlock) {
  for (double s : {0.0, 10.0, 20.0, 30.0}) {
    const Cloud c = plane(s);
    const Grid2D m = build_layers(c.pts, c.ground, square10(), {});
    const float slope = m.at(layer::kSlopeDeg, 10, 10);
    EXPECT_NEAR(slope, s, 0.5) << s;
    EXPECT_EQ(m.at(layer::kImpassable, 10, 10), s > 25 ? 1.f : 0.f) << s;
    EXPECT_NEAR(m.at(layer::kRoughness, 10, 10), 0.0, 1e-3);
    if (s < 25) {
      EXPECT_GT(m.at(layer::kTraversability, 10, 10), 0.5f);
    }
  }
}

TEST(TerrainVoxel, StepsRocksAndOverhangs) {
  Cloud c = plane(0);
  for (auto& p : c.pts)
    if (p.x() > 5.0) p.z() -= 0.35;  // a 0.35 m drop along x = 5
  // A rock of 0.4 m at (2.25, 2.25), an overhanging branch 1.6 m above (7.75, 7.75).
  for (double z = 0.05; z < 0.4; z += 0.05) {
    c.pts.emplace_back(2.2, 2.2, z), c.ground.push_back(0);
    c.pts.emplace_back(2.3, 2.3, z), c.ground.push_back(0);
    c.pts.emplace_back(7.7, 7.7, 1.6 - 0.35 + z), c.ground.push_back(0);
  }
  const Grid2D m = build_layers(c.pts, c.ground, square10(), {});
  EXPECT_EQ(m.at(layer::kImpassable, 4, 4), 1.f);  // the rock
  EXPECT_EQ(m.at(layer::kObstacleProjected, 4, 4), 1.f);
  EXPECT_EQ(m.at(layer::kImpassable, 15, 15), 0.f);  // under the branch
  EXPECT_EQ(m.at(layer::kImpassable, 2, 15), 0.f);   // flat, far from the edge
  // The cells holding the drop's edge carry a step above h_max.
  EXPECT_GT(std::max(m.at(layer::kStep, 9, 12), m.at(layer::kStep, 10, 12)), 0.2f);
  EXPECT_EQ(std::max(m.at(layer::kImpassable, 9, 12), m.at(layer::kImpassable, 10, 12)), 1.f);
  // The seed's method has no projection: the rock's cell is judged by slope and step only.
  const Grid2D s = build_layers(c.pts, c.ground, square10(), seed004_config());
  EXPECT_EQ(s.at(layer::kObstacleProjected, 4, 4), 0.f);
}

TEST(TerrainVoxel, UnknownStaysUnknown) {
  const std::vector<Eigen::Vector3d> none;
  const std::vector<std::uint8_t> flags;
  const Grid2D m = build_layers(none, flags, square10(), {});
  for (float v : m.layer(layer::kTraversability)) EXPECT_TRUE(std::isnan(v));
  for (float v : m.layer(layer::kPoints)) EXPECT_EQ(v, 0.f);
  std::vector<Eigen::Vector3d> nan = {Eigen::Vector3d::Constant(std::nan(""))};
  std::vector<std::uint8_t> f1 = {1};
  EXPECT_NO_THROW(build_layers(nan, f1, square10(), {}));
  const PointCloud empty;
  const Grid2D e = map_scan(empty, SensorModel::vlp16(), Pose::Identity());
  for (float v : e.layer(layer::kImpassable)) EXPECT_TRUE(std::isnan(v));
}
