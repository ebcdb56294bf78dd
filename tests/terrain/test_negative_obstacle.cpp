// Trench shadows (negative_obstacle.hpp) on one synthetic VLP-16 scan, ray-cast over flat ground
// holding a trench ahead, a rock on one side and a crest falling away on the other: the trench's
// hidden cells are marked before any return is seen in them, the shadows behind the rock and
// beyond the crest are not.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "fieldlidar/terrain/negative_obstacle.hpp"
#include "fieldlidar/terrain/terrain_map.hpp"

using namespace fieldlidar;
using namespace fieldlidar::terrain;

namespace {

constexpr double kSensorZ_m = 1.2;

/// The ground (m): level, but a trench across x = 9.3-11.3 m for |y| < 4 m (0.8 m deep, cosine
/// section, as the simulated scene's ditch; the -7 deg beam meets the level ground inside it, at
/// 9.8 m, and comes back from its far wall), and for y > 5 m (|x| < 4 m) a bank rising at 11 deg
/// to a crest 0.6 m high at y = 8 m that falls away beyond at 20 deg (drivable) to 1.5 m below.
double ground_z(double x, double y) {
  if (std::abs(x - 10.3) < 1.0 && std::abs(y) < 4.0)
    return -0.4 * (1.0 + std::cos(M_PI * (x - 10.3)));
  if (y > 5.0 && std::abs(x) < 4.0) {
    if (y < 8.0) return 0.2 * (y - 5.0);
    return std::max(-1.5, 0.6 - std::tan(20.0 * M_PI / 180.0) * (y - 8.0));
  }
  return 0.0;
}

/// A rock: a 0.8 x 0.6 m block 0.5 m high centred on (0, -6).
bool in_rock(double x, double y, double z) {
  return std::abs(x) < 0.4 && std::abs(y + 6.0) < 0.3 && z < 0.5;
}

struct Scan {
  std::vector<Eigen::Vector3d> pts;
  std::vector<std::uint8_t> ground;
};

/// The downward beams of a VLP-16 (-15 .. -1 deg, 1800 columns) from (0, 0, kSensorZ_m), marched
/// in 2 cm steps from where the beam is 0.6 m above the level ground (nothing stands higher, the
/// crest aside) to 40 m; rock returns are not ground.
Scan cast() {
  Scan s;
  for (int ring = 0; ring < 8; ++ring) {
    const double el = (-15.0 + 2.0 * ring) * M_PI / 180.0;
    for (int col = 0; col < 1800; ++col) {
      const double az = 2.0 * M_PI * col / 1800.0;
      const Eigen::Vector3d d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az),
                              std::sin(el));
      for (double t = std::max(0.5, (kSensorZ_m - 0.7) / -d.z()); t < 40.0; t += 0.02) {
        const Eigen::Vector3d p = Eigen::Vector3d(0, 0, kSensorZ_m) + t * d;
        const bool rock = in_rock(p.x(), p.y(), p.z());
        if (!rock && p.z() > ground_z(p.x(), p.y())) continue;
        s.pts.push_back(p);
        s.ground.push_back(rock ? 0 : 1);
        break;
      }
    }
  }
  return s;
}

int flagged(const Grid2D& map, double x0, double x1, double y0, double y1) {
  int n = 0;
  for (double x = x0 + 0.25; x < x1; x += 0.5)
    for (double y = y0 + 0.25; y < y1; y += 0.5)
      if (const auto v = map.value_at(layer::kNegativeObstacle, {x, y}); v && *v > 0.5f) ++n;
  return n;
}

}  // namespace

TEST(TerrainNegativeObstacle, TrenchMarkedBeforeSeenRockAndCrestShadowsNot) {
  const Scan scan = cast();
  const Eigen::Vector3d sensor(0, 0, kSensorZ_m);
  const auto shadows = find_trench_shadows(scan.pts, scan.ground, sensor, 25.0, {}).shadows;
  ASSERT_GT(shadows.size(), 20u);
  for (const auto& s : shadows) {  // every hidden span lies over the trench (and its lip)
    EXPECT_GT(s.from_m.x(), 9.3) << s.from_m.transpose();
    EXPECT_LT(s.to_m.x(), 11.3) << s.to_m.transpose();
    EXPECT_LT(std::abs(s.to_m.y()), 4.5) << s.to_m.transpose();
  }

  TerrainMap map;
  map.add_points(scan.pts, scan.ground, sensor);
  const Grid2D g = map.global_map();
  // The trench's cells ahead (|y| < 2 m): marked, and still unknown in the other layers.
  const int trench = flagged(g, 9.0, 11.5, -2.0, 2.0);
  std::printf("%zu trench shadows, %d cells marked ahead (|y| < 2 m), %d in all\n", shadows.size(),
              trench, flagged(g, -30.0, 30.0, -30.0, 30.0));
  EXPECT_GE(trench, 24);
  for (double x = 9.25; x < 11.5; x += 0.5)
    for (double y = -1.75; y < 2.0; y += 0.5)
      if (*g.value_at(layer::kNegativeObstacle, {x, y}) > 0.5f) {
        EXPECT_FALSE(std::isfinite(*g.value_at(layer::kTraversability, {x, y}))) << x << " " << y;
      }
  // Nothing behind the rock, beyond the crest, or anywhere off the trench.
  EXPECT_EQ(flagged(g, -3.0, 3.0, -20.0, -3.0), 0);
  EXPECT_EQ(flagged(g, -4.0, 4.0, 5.0, 30.0), 0);
  EXPECT_EQ(flagged(g, -30.0, 30.0, -30.0, 30.0), flagged(g, 9.0, 11.5, -4.5, 4.5));
  // Off: no mark.
  FusionConfig off;
  off.negative_obstacles.enabled = false;
  TerrainMap plain(off);
  plain.add_points(scan.pts, scan.ground, sensor);
  EXPECT_EQ(flagged(plain.global_map(), -30.0, 30.0, -30.0, 30.0), 0);
}

// Ground seen in a marked cell overrides the mark: the same trench filled in (level ground there)
// and seen from 3.3 m before it.
TEST(TerrainNegativeObstacle, GroundSeenSinceOverridesTheMark) {
  const Scan scan = cast();
  TerrainMap map;
  map.add_points(scan.pts, scan.ground, {0, 0, kSensorZ_m});
  ASSERT_GE(flagged(map.global_map(), 9.0, 11.5, -2.0, 2.0), 16);
  std::vector<Eigen::Vector3d> level;
  std::vector<std::uint8_t> ground;
  for (double x = 3.05; x < 16.0; x += 0.1)
    for (double y = -5.95; y < 6.0; y += 0.1) {
      level.emplace_back(x, y, 0.0);
      ground.push_back(1);
    }
  map.add_points(level, ground, {6.0, 0.0, kSensorZ_m});
  EXPECT_EQ(flagged(map.global_map(), 9.0, 11.5, -2.0, 2.0), 0);
}

// The polynomial azimuth column is std::atan2's column everywhere: swept in steps finer than a
// column, and right at each column's edges (where it defers to std::atan2).
TEST(TerrainNegativeObstacle, AzimuthColumnIsAtan2Column) {
  const double column_rad = 0.4 * std::numbers::pi / 180.0;
  const int columns = int(std::ceil(2 * std::numbers::pi / column_rad));
  const auto atan2_column = [&](double dx, double dy) {
    return std::min(columns - 1, int((std::atan2(dy, dx) + std::numbers::pi) / column_rad));
  };
  int checked = 0, differ = 0;
  for (int k = 0; k <= 2'000'000; ++k) {
    const double a = -std::numbers::pi + 2 * std::numbers::pi * k / 2'000'000.0;
    for (const double r : {0.7, 13.0, 95.0}) {
      const double dx = r * std::cos(a), dy = r * std::sin(a);
      differ += detail::azimuth_column(dx, dy, column_rad, columns) != atan2_column(dx, dy);
      ++checked;
    }
  }
  for (int c = 0; c <= columns; ++c)
    for (const double off : {-1e-9, 0.0, 1e-9, 1e-5, -1e-5}) {
      const double a = -std::numbers::pi + c * column_rad + off;
      const double dx = std::cos(a), dy = std::sin(a);
      differ += detail::azimuth_column(dx, dy, column_rad, columns) != atan2_column(dx, dy);
      ++checked;
    }
  for (const double dx : {-1.0, 1.0, 0.0})
    for (const double dy : {-0.0, 0.0, -1.0, 1.0})
      if (dx != 0 || dy != 0) {
        differ += detail::azimuth_column(dx, dy, column_rad, columns) != atan2_column(dx, dy);
        ++checked;
      }
  EXPECT_EQ(differ, 0) << "of " << checked;
}
