// The fused map on a hill's flank (synthetic returns): returns the ground segmentation left out
// of the ground on a slope the robot can climb are no obstacle, a rock on the same slope is.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "fieldlidar/terrain/terrain_map.hpp"

using namespace fieldlidar;
using namespace fieldlidar::terrain;

namespace {

/// Returns every 0.1 m on the plane z = tan(20 deg) x over [0, 10]^2, ground but in the cell
/// (5, 5)-(5.5, 5.5) (left out of the ground, as a segmentation does on a face); with `rock`, a
/// 0.3 m high block of non-ground returns on the cell (7, 5)-(7.5, 5.5).
struct Flank {
  std::vector<Eigen::Vector3d> pts;
  std::vector<std::uint8_t> ground;
  explicit Flank(bool rock) {
    const double t = std::tan(20.0 * M_PI / 180.0);
    for (int i = 0; i < 100; ++i)
      for (int j = 0; j < 100; ++j) {
        const double x = 0.05 + 0.1 * i, y = 0.05 + 0.1 * j;
        const bool face = x > 5.0 && x < 5.5 && y > 5.0 && y < 5.5;
        pts.emplace_back(x, y, t * x);
        ground.push_back(face ? 0 : 1);
        if (rock && x > 7.0 && x < 7.5 && y > 5.0 && y < 5.5) {
          pts.emplace_back(x, y, t * x + 0.3);
          ground.push_back(0);
        }
      }
  }
};

bool obstacle(const TerrainMap& map, const Eigen::Vector2d& c) {
  const auto v = map.global_map().value_at(layer::kObstacleProjected, c);
  return v && *v == 1.0f;
}

}  // namespace

// Seen from (0, 5) 3 m up: measured from the lowest ground near it (the downhill neighbour's,
// 0.18-0.36 m below), the face cell's returns stood in the robot's body; from the plane of the
// ground returns around them they are on the ground. The rock stands 0.3 m above it either way.
TEST(TerrainFusionFlank, SlopeLeftOutOfTheGroundIsNoObstacleARockIs) {
  const Flank flank(true);
  const Eigen::Vector2d face(5.25, 5.25), rock(7.25, 5.25);
  TerrainMap with_plane;
  with_plane.add_points(flank.pts, flank.ground, {0, 5, 3});
  EXPECT_FALSE(obstacle(with_plane, face));
  EXPECT_TRUE(obstacle(with_plane, rock));
  FusionConfig lowest;
  lowest.obstacle_height_from_scan_plane = false;
  TerrainMap without_plane(lowest);
  without_plane.add_points(flank.pts, flank.ground, {0, 5, 3});
  EXPECT_TRUE(obstacle(without_plane, face));
  EXPECT_TRUE(obstacle(without_plane, rock));
  // The flank itself (20 deg, under the robot's 25 less the planes' 3 deg margin) is passable.
  EXPECT_EQ(*with_plane.global_map().value_at(layer::kImpassable, {2.25, 2.25}), 0.0f);
  EXPECT_NEAR(*with_plane.global_map().value_at(layer::kSlopeDeg, {2.25, 2.25}), 20.0, 0.1);
}
