// The fused map on synthetic returns with exact answers: statistics add up across scans, layers
// follow, obstacle evidence decays when the ground is seen again, unknown stays unknown.
#include <cmath>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/terrain/terrain_map.hpp"

using namespace fieldlidar;
using namespace fieldlidar::terrain;

namespace {

/// Ground returns of the plane z = tan(slope) x over [0, 10]^2 every `spacing` m, shifted by
/// `phase`.
void plane(double slope_deg, double spacing, double phase, std::vector<Eigen::Vector3d>& pts,
           std::vector<std::uint8_t>& ground) {
  const int n = int(std::lround(10.0 / spacing));
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double x = phase + i * spacing, y = phase + j * spacing;
      pts.emplace_back(x, y, std::tan(slope_deg * M_PI / 180) * x);
      ground.push_back(1);
    }
}

/// Level ground every 0.1 m, alone and with a person's returns (0.2-0.9 m up) at (5.2, 5.2).
struct LevelGroundWithPerson {
  std::vector<Eigen::Vector3d> pts;
  std::vector<std::uint8_t> ground;
  std::vector<Eigen::Vector3d> with_person;
  std::vector<std::uint8_t> g_person;
  LevelGroundWithPerson() {
    plane(0.0, 0.1, 0.05, pts, ground);
    with_person = pts;
    g_person = ground;
    for (double z = 0.2; z < 1.0; z += 0.1)
      with_person.emplace_back(5.2, 5.2, z), g_person.push_back(0);
  }
};

}  // namespace

TEST(TerrainFusionCells, TwoSparseScansMakeOneDenseMap) {
  TerrainMap map;
  std::vector<Eigen::Vector3d> a, b;
  std::vector<std::uint8_t> ga, gb;
  plane(10.0, 0.2, 0.05, a, ga);
  plane(10.0, 0.2, 0.15, b, gb);
  map.add_points(a, ga, {5, 5, 1});
  const Grid2D one = map.global_map();
  const auto u = map.add_points(b, gb, {5, 5, 1});
  EXPECT_EQ(map.scans(), 2u);
  EXPECT_EQ(u.cells_touched, 400u);
  const Grid2D two = map.global_map();
  const Eigen::Vector2d c(5.25, 5.25);
  EXPECT_EQ(*one.value_at(layer::kPoints, c), 9.0f);   // x, y in {5.05, 5.25, 5.45}
  EXPECT_EQ(*two.value_at(layer::kPoints, c), 13.0f);  // and {5.15, 5.35}
  EXPECT_NEAR(*two.value_at(layer::kSlopeDeg, c), 10.0, 0.1);
  EXPECT_EQ(*two.value_at(layer::kImpassable, c), 0.0f);
  EXPECT_NEAR(*two.value_at(layer::kElevation, c), std::tan(10 * M_PI / 180) * 5.25, 0.01);
  // The rolling local map is the same cells around a centre; outside the drive: unknown.
  const Grid2D local = map.local_map({5, 5}, 4.0);
  EXPECT_EQ(local.geometry().width, 8);
  EXPECT_EQ(*local.value_at(layer::kSlopeDeg, c), *two.value_at(layer::kSlopeDeg, c));
  EXPECT_TRUE(std::isnan(*map.local_map({50, 50}, 4.0).value_at(layer::kImpassable, {50, 50})));
  // The rolling local map follows the last scan's sensor (local_side_m around it).
  const Grid2D rolling = map.local_map();
  EXPECT_EQ(rolling.geometry().width, 80);  // 40 m / 0.5 m
  EXPECT_NEAR(rolling.geometry().origin_m.x(), 5.0 - 20.0, 1e-9);
  EXPECT_EQ(*rolling.value_at(layer::kSlopeDeg, c), *two.value_at(layer::kSlopeDeg, c));
}

TEST(TerrainFusionCells, ObstacleEvidenceDecaysWhenTheGroundIsSeenAgain) {
  TerrainMap map;
  const LevelGroundWithPerson scene;
  const auto& [pts, ground, with_person, g_person] = scene;
  const Eigen::Vector2d c(5.25, 5.25);
  map.add_points(with_person, g_person, {0, 0, 1});
  EXPECT_EQ(*map.global_map().value_at(layer::kObstacleProjected, c), 1.0f);
  EXPECT_EQ(*map.global_map().value_at(layer::kImpassable, c), 1.0f);
  map.add_points(pts, ground, {0, 0, 1});
  map.add_points(pts, ground, {0, 0, 1});
  EXPECT_EQ(*map.global_map().value_at(layer::kObstacleProjected, c), 0.0f);
  EXPECT_EQ(*map.global_map().value_at(layer::kImpassable, c), 0.0f);
}

// Evidence per time: a person in a cell seen free half a second before. Hit by one sweep 0.1 s
// later (10 Hz) the cell stays free (-0.7 + 0.2 * 0.85 < 0); after five such sweeps it blocks;
// scans without stamps, or 0.5 s apart, count whole (one hit: -0.7 + 0.85 > 0).
TEST(TerrainFusionCells, EvidenceCountsPerTimeNotPerSweep) {
  const LevelGroundWithPerson scene;
  const auto& [pts, ground, with_person, g_person] = scene;
  const Eigen::Vector2d c(5.25, 5.25);
  const auto blocked = [&](const TerrainMap& m) {
    return *m.global_map().value_at(layer::kObstacleProjected, c) == 1.0f;
  };
  TerrainMap sweeps, unstamped, slow;
  sweeps.add_points(pts, ground, {0, 0, 1}, 10.0);
  sweeps.add_points(with_person, g_person, {0, 0, 1}, 10.1);
  EXPECT_FALSE(blocked(sweeps));
  for (double t : {10.2, 10.3, 10.4}) sweeps.add_points(with_person, g_person, {0, 0, 1}, t);
  EXPECT_FALSE(blocked(sweeps));  // -0.7 + 4 * 0.17
  sweeps.add_points(with_person, g_person, {0, 0, 1}, 10.5);
  EXPECT_TRUE(blocked(sweeps));
  unstamped.add_points(pts, ground, {0, 0, 1});
  unstamped.add_points(with_person, g_person, {0, 0, 1});
  EXPECT_TRUE(blocked(unstamped));
  slow.add_points(pts, ground, {0, 0, 1}, 10.0);
  slow.add_points(with_person, g_person, {0, 0, 1}, 10.5);
  EXPECT_TRUE(blocked(slow));
  FusionConfig bad;
  bad.evidence_period_s = -1;
  EXPECT_THROW(TerrainMap{bad}, Error);
}

TEST(TerrainFusionCells, BadInputGivesUnknownOrAClearError) {
  TerrainMap map;
  const std::vector<Eigen::Vector3d> nan = {Eigen::Vector3d::Constant(std::nan(""))};
  const std::vector<std::uint8_t> one = {1}, none;
  EXPECT_EQ(map.add_points(nan, one, {0, 0, 0}).points, 0u);
  EXPECT_EQ(map.global_map().geometry().cell_count(), 0u);
  EXPECT_THROW(map.add_points(nan, none, {0, 0, 0}), Error);
  // A finite point no cell index can hold (1e30 m: another unit) is named, not cast to int.
  const std::vector<Eigen::Vector3d> far = {{1e30, 0, 0}};
  try {
    map.add_points(far, one, {0, 0, 0});
    FAIL() << "a point at 1e30 m must be refused";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("1e+30 m"), std::string::npos) << e.what();
  }
  EXPECT_THROW(map.local_map({std::nan(""), 0}, 40.0), Error);
  // No ground at all: a wall of non-ground returns is never free.
  std::vector<Eigen::Vector3d> wall;
  std::vector<std::uint8_t> flags;
  for (double y = 0; y < 3; y += 0.05)
    for (double z = 0; z < 2; z += 0.05) wall.emplace_back(2.0, y, z), flags.push_back(0);
  map.add_points(wall, flags, {0, 0, 1});
  const Grid2D walled = map.global_map();
  const auto tau = walled.layer(layer::kTraversability);
  for (std::size_t i = 0; i < tau.size(); ++i) EXPECT_FALSE(tau[i] > 0.0f) << i;
  map.add_scan(PointCloud{}, SensorModel::vlp16(), Pose::Identity());
  FusionConfig absurd;
  absurd.layers.robot.width_m = 1e6;
  EXPECT_THROW(TerrainMap{absurd}, Error);
  absurd = {};
  absurd.layers.robot.max_slope_deg = 90;
  EXPECT_THROW(TerrainMap{absurd}, Error);
}

// A low rock the ground segmentation keeps as ground (0.19 m: above the robot's 0.15 m
// min_obstacle_height, below its 0.20 m max_step) stands above its neighbours on both sides: an
// obstacle, with a rim of its 4 neighbour cells. A 0.17 m terrace step, higher on one side only, is
// a step the robot takes.
TEST(TerrainFusionCells, LowRockKeptAsGroundBlocksAStepDoesNot) {
  std::vector<Eigen::Vector3d> pts;
  std::vector<std::uint8_t> ground;
  for (double x = 0.025; x < 10; x += 0.05)
    for (double y = 0.025; y < 10; y += 0.05) {
      double z = x > 7.0 ? 0.17 : 0.0;  // the terrace
      const double r = std::hypot(x - 3.25, y - 5.25);
      if (r < 0.25) z = 0.19 * std::sqrt(1 - r * r / 0.0625);  // the rock: a 0.25 m half-ellipsoid
      pts.emplace_back(x, y, z);
      ground.push_back(1);
    }
  TerrainMap map;
  map.add_points(pts, ground, {5, 5, 1.2});
  const Grid2D m = map.global_map();
  EXPECT_EQ(*m.value_at(layer::kImpassable, {3.25, 5.25}), 1.0f);
  EXPECT_EQ(*m.value_at(layer::kImpassable, {3.25, 6.25}), 0.0f);  // two cells off the rock
  EXPECT_EQ(*m.value_at(layer::kImpassable, {6.75, 5.25}), 0.0f);  // below the terrace's edge
  EXPECT_EQ(*m.value_at(layer::kImpassable, {7.25, 5.25}), 0.0f);  // on it
  // Its rim: the 4 neighbours block too, as an obstacle's do (the truth marks every cell the
  // rock's disk touches; a 0.18 m rock on terrain seed 0 was marked in one of its two cells).
  for (const Eigen::Vector2d& rim : {Eigen::Vector2d(2.75, 5.25), Eigen::Vector2d(3.75, 5.25),
                                     Eigen::Vector2d(3.25, 4.75), Eigen::Vector2d(3.25, 5.75)})
    EXPECT_EQ(*m.value_at(layer::kImpassable, rim), 1.0f) << rim.transpose();
  EXPECT_EQ(*m.value_at(layer::kImpassable, {3.75, 5.75}), 0.0f);  // diagonal: no rim
  FusionConfig no_bump;
  no_bump.bump_obstacles = false;
  TerrainMap without(no_bump);
  without.add_points(pts, ground, {5, 5, 1.2});
  EXPECT_EQ(*without.global_map().value_at(layer::kImpassable, {3.25, 5.25}), 0.0f);
}

// The slope of an impassable cell is the ground's around it, not the rock's: a low rock (0.25 m,
// 0.3 m radius) kept as ground on a 10 deg slope, across two cells, blocks them and their rim;
// their slope is read from the clear cells around them (9.9-10.1 deg; their own planes say 39 and
// 24 deg). The classification is the same either way.
TEST(TerrainFusionCells, BlockedCellsGetTheGroundsSlope) {
  std::vector<Eigen::Vector3d> pts;
  std::vector<std::uint8_t> ground;
  const double rise = std::tan(10.0 * M_PI / 180);
  for (double x = 0.025; x < 10; x += 0.05)
    for (double y = 0.025; y < 10; y += 0.05) {
      double z = rise * x;
      const double r = std::hypot(x - 3.5, y - 5.25);
      if (r < 0.3) z += 0.25 * std::sqrt(1 - r * r / 0.09);
      pts.emplace_back(x, y, z);
      ground.push_back(1);
    }
  const std::vector<Eigen::Vector2d> blocked = {{3.25, 5.25}, {3.75, 5.25}, {2.75, 5.25},
                                                {4.25, 5.25}, {3.25, 4.75}, {3.75, 5.75}};
  FusionConfig own_plane;
  own_plane.blocked_slope_from_clear_ground = false;
  for (const FusionConfig& config : {FusionConfig{}, own_plane}) {
    TerrainMap map(config);
    map.add_points(pts, ground, {5, 5, 1.2 + rise * 5});
    const Grid2D m = map.global_map();
    for (const Eigen::Vector2d& c : blocked) {
      EXPECT_EQ(*m.value_at(layer::kImpassable, c), 1.0f) << c.transpose();
      const float slope = *m.value_at(layer::kSlopeDeg, c);
      std::printf("%s (%.2f, %.2f): slope %.2f\n",
                  config.blocked_slope_from_clear_ground ? "clear" : "own", c.x(), c.y(), slope);
      if (config.blocked_slope_from_clear_ground) {
        EXPECT_NEAR(slope, 10.0, 0.5) << c.transpose();
      }
    }
    if (!config.blocked_slope_from_clear_ground) {  // the rock's two cells, from their own returns
      EXPECT_GT(*m.value_at(layer::kSlopeDeg, blocked[0]), 20.0f);
      EXPECT_GT(*m.value_at(layer::kSlopeDeg, blocked[1]), 20.0f);
    }
    EXPECT_NEAR(*m.value_at(layer::kSlopeDeg, {3.25, 6.25}), 10.0, 0.1);  // passable: as before
  }
}

// A branch over a track, seen from afar, that the ground segmentation took for ground (terrain
// seed 0: strips of impassable cells 3-7 m long under the branches, which sent the navigate loop
// round them): returns more than the clearance above the ground near them are no ground. Seen
// with the ground beside it, or first alone and then with the ground under it, the branch leaves
// the track passable.
TEST(TerrainFusionCells, OverhangTakenForGroundLeavesTheTrackPassable) {
  std::vector<Eigen::Vector3d> ground_pts, branch;
  std::vector<std::uint8_t> g_ground, g_branch;
  for (double x = 0.05; x < 10; x += 0.1)
    for (double y = 0.05; y < 10; y += 0.1) {
      if (x > 5.0 && x < 5.5) continue;  // under the branch: hidden in the first scan
      ground_pts.emplace_back(x, y, 0.02 * x), g_ground.push_back(1);
    }
  for (double y = 2.02; y < 8; y += 0.05)  // one ring's line along the branch, 2.4 m up
    branch.emplace_back(5.3, y, 2.4), g_branch.push_back(1);
  const Eigen::Vector2d under(5.25, 5.25), beside(4.75, 5.25);
  // One scan: the branch with the ground beside it.
  std::vector<Eigen::Vector3d> both = ground_pts;
  std::vector<std::uint8_t> g_both = g_ground;
  both.insert(both.end(), branch.begin(), branch.end());
  g_both.insert(g_both.end(), g_branch.begin(), g_branch.end());
  TerrainMap one;
  one.add_points(both, g_both, {5, 0, 1.2});
  // The ground under the branch is hidden: unknown there and next to it, not impassable.
  EXPECT_FALSE(*one.global_map().value_at(layer::kImpassable, under) > 0.5f);
  EXPECT_FALSE(*one.global_map().value_at(layer::kImpassable, beside) > 0.5f);
  EXPECT_EQ(*one.global_map().value_at(layer::kImpassable, {4.25, 5.25}), 0.0f);
  // The branch alone first (nothing near it seen yet: taken for ground), then the ground under
  // and beside it: the cells drop the branch and are passable.
  TerrainMap two;
  two.add_points(branch, g_branch, {5, 0, 1.2});
  std::vector<Eigen::Vector3d> all = ground_pts;
  std::vector<std::uint8_t> g_all = g_ground;
  for (double x = 5.05; x < 5.5; x += 0.1)
    for (double y = 0.05; y < 10; y += 0.1) all.emplace_back(x, y, 0.02 * x), g_all.push_back(1);
  two.add_points(all, g_all, {5, 0, 1.2});
  EXPECT_EQ(*two.global_map().value_at(layer::kImpassable, under), 0.0f);
  EXPECT_EQ(*two.global_map().value_at(layer::kImpassable, beside), 0.0f);
  EXPECT_NEAR(*two.global_map().value_at(layer::kElevation, under), 0.02 * 5.25, 0.01);
  // The branch alone first, then the ground beside it only (the ground under it stays hidden):
  // the branch is no ground of its cells, which stay unknown, and the cells beside them are
  // passable (seed 17: a branch seen from 23-25 m blocked the goal's cells with steps of 1 m).
  TerrainMap four;
  four.add_points(branch, g_branch, {-20, 0, 1.2});
  four.add_points(ground_pts, g_ground, {5, 0, 1.2});
  EXPECT_FALSE(four.global_map().value_at(layer::kElevation, under).has_value() &&
               std::isfinite(*four.global_map().value_at(layer::kElevation, under)));
  EXPECT_FALSE(*four.global_map().value_at(layer::kImpassable, under) > 0.5f);
  EXPECT_EQ(*four.global_map().value_at(layer::kImpassable, {4.25, 5.25}), 0.0f);
  EXPECT_LT(*four.global_map().value_at(layer::kStep, {4.25, 5.25}), 0.05f);
  // The branch's tip seen from farther still: one or two returns per cell, fewer than a cell
  // needs to be known (terrain seed 13: one such return stayed in a cell's ground and its step
  // read 0.41 m, blocking the 3 x 3 cells round it for good).
  for (const double spacing : {0.5, 0.25}) {
    std::vector<Eigen::Vector3d> tip;
    for (double y = 2.05; y < 8; y += spacing) tip.emplace_back(5.3, y, 2.4);
    const std::vector<std::uint8_t> g_tip(tip.size(), 1);
    TerrainMap three;
    three.add_points(tip, g_tip, {-20, 0, 1.2});
    three.add_points(all, g_all, {5, 0, 1.2});
    EXPECT_EQ(*three.global_map().value_at(layer::kImpassable, under), 0.0f) << spacing;
    EXPECT_LT(*three.global_map().value_at(layer::kStep, under), 0.05f) << spacing;
    EXPECT_NEAR(*three.global_map().value_at(layer::kElevation, under), 0.02 * 5.25, 0.01)
        << spacing;
  }
}

// A cell no return hit, between seen flat ground (sparse: few returns each side), is bridged by
// the ground model: its neighbours are passable rather than unknown. The same gap beside many
// returns (a shadow) or beside an obstacle is not bridged. The gap itself stays unknown.
TEST(TerrainFusionCells, SmallGapBridgedButNotAShadow) {
  const auto flat = [](double spacing, std::vector<Eigen::Vector3d>& pts,
                       std::vector<std::uint8_t>& ground) {
    for (double x = spacing / 2; x < 6; x += spacing)
      for (double y = spacing / 2; y < 6; y += spacing) {
        if (x > 3.0 && x < 3.5 && y > 3.0 && y < 3.5) continue;  // the gap: cell (6, 6)
        pts.emplace_back(x, y, 0.0);
        ground.push_back(1);
      }
  };
  const Eigen::Vector2d beside(2.75, 3.25), gap(3.25, 3.25);
  std::vector<Eigen::Vector3d> sparse, dense;
  std::vector<std::uint8_t> gs, gd;
  flat(0.125, sparse, gs);  // 16 returns a cell
  flat(0.05, dense, gd);    // 100 a cell
  FusionConfig no_bridge;
  no_bridge.max_bridged_cells = 0;
  TerrainMap a, b, strict(no_bridge);
  a.add_points(sparse, gs, {3, 3, 1.2});
  strict.add_points(sparse, gs, {3, 3, 1.2});
  b.add_points(dense, gd, {3, 3, 1.2});
  EXPECT_EQ(*a.global_map().value_at(layer::kImpassable, beside), 0.0f);
  EXPECT_TRUE(std::isnan(*a.global_map().value_at(layer::kImpassable, gap)));
  EXPECT_TRUE(std::isnan(*strict.global_map().value_at(layer::kImpassable, beside)));
  EXPECT_TRUE(std::isnan(*b.global_map().value_at(layer::kImpassable, beside)));
  // An obstacle next to the gap: no bridge (and the obstacle's halo blocks its 4 neighbours).
  std::vector<Eigen::Vector3d> rock = sparse;
  std::vector<std::uint8_t> gr = gs;
  for (int k = 0; k < 6; ++k) rock.emplace_back(3.6 + 0.05 * k, 3.25, 0.5), gr.push_back(0);
  TerrainMap c;
  c.add_points(rock, gr, {3, 3, 1.2});
  const Eigen::Vector2d below(3.25, 2.75);  // the gap and the rock's cell are in its window
  EXPECT_EQ(*a.global_map().value_at(layer::kImpassable, below), 0.0f);
  EXPECT_TRUE(std::isnan(*c.global_map().value_at(layer::kImpassable, below)));
}

// A survey through the fused cells: flat ground with a lake (water returns, e.g. LAS class 9) is
// passable on land and impassable on the water, which is flat too; flags that do not match the
// points are a clear error.
TEST(TerrainFusionCells, SurveyWaterIsImpassable) {
  PointCloud cloud;
  std::vector<std::uint8_t> water;
  for (double x = 0.1; x < 12; x += 0.2)
    for (double y = 0.1; y < 12; y += 0.2) {
      Point p;
      p.x = float(x), p.y = float(y), p.z = 0.0f;
      cloud.push_back(p);
      water.push_back(x > 6.0);
    }
  FusionConfig config;
  config.layers.cell_m = 1.0;
  const Grid2D m = map_area_fused(cloud, config, water);
  EXPECT_EQ(*m.value_at(layer::kImpassable, {3.5, 6.5}), 0.0f);
  EXPECT_EQ(*m.value_at(layer::kImpassable, {9.5, 6.5}), 1.0f);
  EXPECT_EQ(*m.value_at(layer::kTraversability, {9.5, 6.5}), 0.0f);
  EXPECT_EQ(*map_area_fused(cloud, config).value_at(layer::kImpassable, {9.5, 6.5}), 0.0f);
  water.pop_back();
  EXPECT_THROW(map_area_fused(cloud, config, water), Error);
}
