// Hybrid A* on hand-built maps with known answers: a corridor, a maze, a U-trap that needs a
// reverse manoeuvre, an unreachable goal, a field of low tau the plan goes round, and searches
// hurried past late_expansions.

#include <cmath>
#include <cstdio>
#include <random>

#include <gtest/gtest.h>

#include "fieldlidar/planning/hybrid_astar.hpp"
#include "test_maps.hpp"

namespace fieldlidar::planning {
namespace {

using test::block;
using test::open_map;

bool has_reverse(const Path& p) {
  for (const auto& s : p)
    if (s.reverse) return true;
  return false;
}

TEST(HybridAStar, CorridorIsDrivenStraight) {
  Grid2D map = open_map(30, 6);
  block(map, 0, 0, 30, 1.5);
  block(map, 0, 4.0, 30, 6);
  HybridAStar planner(map, {});
  const auto r = planner.plan({2, 2.75, 0}, {28, 2.75, 0});
  ASSERT_TRUE(r.ok()) << to_string(r.status);
  EXPECT_NEAR(path_length_m(r.path), 26.0, 0.3);
  EXPECT_FALSE(has_reverse(r.path));
  EXPECT_LT(r.expansions, 60);  // measured 16: the heuristic leads straight down the corridor
}

TEST(HybridAStar, MazeIsSolvedRoundBothWalls) {
  Grid2D map = open_map(30, 30);
  block(map, 9, 0, 10, 22);
  block(map, 19, 8, 20, 30);
  HybridAStar planner(map, {});
  const auto r = planner.plan({4, 4, M_PI / 2}, {26, 26, M_PI / 2});
  ASSERT_TRUE(r.ok()) << to_string(r.status);
  const double len = path_length_m(r.path);
  EXPECT_GT(len, 58.0);  // over the first wall's end, under the second's
  EXPECT_LT(len, 75.0);
  for (const auto& s : r.path) EXPECT_FALSE(planner.map().footprint_hits_blocked(s.pose, 0.0));
}

// The maze on 0.25 m cells, searched near the optimum: on a 0.5 m lattice
// (PlannerConfig::lattice_cell_m) it expands about a third of the nodes it does on the map's own
// cells (3,667 against 10,648 measured) for a path 1 % longer, which still keeps the exact
// footprint off every blocked cell.
TEST(HybridAStar, CoarserLatticeOnAFineMapSearchesLess) {
  Grid2D map = open_map(30, 30, 0.25);
  block(map, 9, 0, 10, 22);
  block(map, 19, 8, 20, 30);
  PlannerConfig fine_cfg;
  fine_cfg.heuristic_weight = 1.0;  // a search near the lattice's optimum
  PlannerConfig coarse_cfg = fine_cfg;
  coarse_cfg.lattice_cell_m = 0.5;
  HybridAStar fine(map, {}, fine_cfg), coarse(map, {}, coarse_cfg);
  const Pose2 start{4, 4, M_PI / 2}, goal{26, 26, M_PI / 2};
  const auto f = fine.plan(start, goal), c = coarse.plan(start, goal);
  ASSERT_TRUE(f.ok()) << to_string(f.status);
  ASSERT_TRUE(c.ok()) << to_string(c.status);
  std::printf("maze on 0.25 m cells: own lattice %d expansions, %.2f m; 0.5 m lattice %d, %.2f m\n",
              f.expansions, path_length_m(f.path), c.expansions, path_length_m(c.path));
  EXPECT_LT(2 * c.expansions, f.expansions);
  EXPECT_LT(path_length_m(c.path), 1.05 * path_length_m(f.path));
  for (const auto& s : c.path) EXPECT_FALSE(coarse.map().footprint_hits_blocked(s.pose, 0.0));
  coarse_cfg.lattice_cell_m = -0.5;
  EXPECT_EQ(HybridAStar(map, {}, coarse_cfg).plan(start, goal).status, PlanStatus::kInvalidInput);
  coarse_cfg.lattice_cell_m = std::nan("");
  EXPECT_EQ(HybridAStar(map, {}, coarse_cfg).plan(start, goal).status, PlanStatus::kInvalidInput);
}

TEST(HybridAStar, UTrapNeedsReversing) {
  // A 1.6 m wide dead end (too narrow to turn round at R = 1 m) with the robot facing its end.
  Grid2D map = open_map(24, 30);
  block(map, 8, 13.0, 17, 14.2);
  block(map, 8, 15.8, 17, 17.0);
  block(map, 16, 13.0, 17, 17.0);
  HybridAStar planner(map, {});
  const auto r = planner.plan({14, 15, 0}, {4, 15, M_PI});
  ASSERT_TRUE(r.ok()) << to_string(r.status);
  EXPECT_TRUE(has_reverse(r.path));
  EXPECT_GE(direction_changes(r.path), 1);
  for (const auto& s : r.path) EXPECT_FALSE(planner.map().footprint_hits_blocked(s.pose, 0.0));
}

TEST(HybridAStar, EnclosedGoalIsReportedUnreachableAtOnce) {
  Grid2D map = open_map(30, 30);
  block(map, 18, 18, 28, 19);
  block(map, 18, 27, 28, 28);
  block(map, 18, 18, 19, 28);
  block(map, 27, 18, 28, 28);
  HybridAStar planner(map, {});
  const auto r = planner.plan({4, 4, 0}, {23, 23, 0});
  EXPECT_EQ(r.status, PlanStatus::kNoPath);
  EXPECT_TRUE(r.path.empty());
  EXPECT_LT(r.expansions, 10);  // measured 0: the grid Dijkstra finds the goal enclosed
}

// A wall across the map with one gap: 0.5 m (a cell) lets a point through but not the 0.58 m
// wide robot; 1.5 m lets both through.
Grid2D walled_map(double gap_m) {
  Grid2D map = open_map(30, 20);
  block(map, 14, 0, 15, 9.8 - 0.5 * gap_m);  // cells centred at y 9.75 +- gap / 2 stay open
  block(map, 14, 9.7 + 0.5 * gap_m, 15, 20);
  return map;
}

TEST(HybridAStar, GapTooNarrowForTheFootprintFailsFast) {
  HybridAStar narrow(walled_map(0.5), {});
  const auto r = narrow.plan({5, 9.75, 0}, {25, 9.75, 0});
  EXPECT_EQ(r.status, PlanStatus::kNoPath) << to_string(r.status);
  EXPECT_TRUE(r.path.empty());
  // measured 0: the heuristic's grid closes the gap (no point of it is far enough from the
  // wall for the footprint's inscribed disc); without that the search ran 34,648 expansions
  // (all it could) before it gave up
  EXPECT_LT(r.expansions, 10);
  HybridAStar wide(walled_map(1.5), {});
  const auto w = wide.plan({5, 9.75, 0}, {25, 9.75, 0});
  ASSERT_TRUE(w.ok()) << to_string(w.status);
  std::printf("gap: 0.5 m %s after %d expansions; 1.5 m planned, %.2f m, %d expansions\n",
              to_string(r.status), r.expansions, path_length_m(w.path), w.expansions);
  EXPECT_LT(path_length_m(w.path), 20.5);
  for (const auto& p : w.path) EXPECT_FALSE(wide.map().footprint_hits_blocked(p.pose, 0.0));
}

TEST(HybridAStar, LowTauIsAvoidedWhenADetourIsCheap) {
  Grid2D map = open_map(30, 20);
  auto tau = map.layer(terrain::layer::kTraversability);
  const GridGeometry& g = map.geometry();
  for (int iy = 0; iy < g.height; ++iy)
    for (int ix = 0; ix < g.width; ++ix) {
      const auto c = g.cell_center(ix, iy);
      if (c.x() > 12 && c.x() < 18 && c.y() > 4 && c.y() < 16) tau[g.linear_index(ix, iy)] = 0.1f;
    }
  PlannerConfig c;
  c.heuristic_weight = 1.0;  // weighted A* may accept a path up to w times costlier
  HybridAStar planner(map, {}, c);
  const auto r = planner.plan({3, 10, 0}, {27, 10, 0});
  ASSERT_TRUE(r.ok()) << to_string(r.status);
  int in_low = 0;
  for (const auto& s : r.path) {
    const long i = planner.map().cell_index(s.pose.x_m, s.pose.y_m);
    in_low += planner.map().tau(std::size_t(i)) < 0.5f;
  }
  EXPECT_EQ(in_low, 0);
}

TEST(HybridAStar, SmoothingShortensAndStraightensWithinBounds) {
  Grid2D map = open_map(40, 40);
  block(map, 12, 0, 14, 25);
  block(map, 24, 15, 26, 40);
  PlannerConfig c;
  c.shortcut = false;  // the smoothing of the lattice path itself
  HybridAStar planner(map, {}, c);
  const auto r = planner.plan({4, 4, 0}, {36, 36, 0});
  ASSERT_TRUE(r.ok()) << to_string(r.status);
  const auto& s = r.smoothing;
  EXPECT_LT(s.length_after_m, s.length_before_m - 0.2);         // 71.06 -> 70.70 m
  EXPECT_LT(s.turning_after_rad, 0.92 * s.turning_before_rad);  // 13.28 -> 11.59 rad
  EXPECT_GT(s.blend, 0.5);
  EXPECT_LE(s.max_curvature_after, 1.0 / c.min_turn_radius_m * (1 + 1e-6));
  for (const auto& p : r.path) EXPECT_FALSE(planner.map().footprint_hits_blocked(p.pose, 0.0));
  std::printf(
      "smoothing: length %.2f -> %.2f m, turning %.2f -> %.2f rad, blend %.2f, %d it, %.1f ms, "
      "search %.1f ms, %d exp\n",
      s.length_before_m, s.length_after_m, s.turning_before_rad, s.turning_after_rad, s.blend,
      s.iterations, r.smooth_ms, r.search_ms, r.expansions);
  RecordProperty("length_before_m", std::to_string(s.length_before_m));
  RecordProperty("length_after_m", std::to_string(s.length_after_m));
}

TEST(HybridAStar, ShortcutsTakeTheLatticeZigzagOut) {
  Grid2D map = open_map(40, 40);
  block(map, 12, 0, 14, 25);
  block(map, 24, 15, 26, 40);
  PlannerConfig c;
  c.smooth = false;
  HybridAStar planner(map, {}, c);
  const auto r = planner.plan({4, 4, 0}, {36, 36, 0});
  ASSERT_TRUE(r.ok()) << to_string(r.status);
  const double raw = path_length_m(r.raw_path), cut = path_length_m(r.path);
  std::printf("shortcuts: %d, length %.2f -> %.2f m, %.2f ms\n", r.shortcuts, raw, cut,
              r.shortcut_ms);
  EXPECT_GE(r.shortcuts, 1);
  EXPECT_LT(cut, raw - 2.0);  // measured 71.06 -> 67.48 m
  EXPECT_LE(max_curvature(r.path), 1.0 / c.min_turn_radius_m * (1 + 1e-6));
  EXPECT_NEAR(r.path.front().pose.x_m, 4.0, 1e-9);
  EXPECT_NEAR(r.path.back().pose.x_m, r.raw_path.back().pose.x_m, 1e-9);
  EXPECT_NEAR(r.path.back().pose.yaw_rad, r.raw_path.back().pose.yaw_rad, 1e-9);
  for (const auto& p : r.path) EXPECT_FALSE(planner.map().footprint_hits_blocked(p.pose, 0.0));
}

// A search past late_expansions goes on at late_heuristic_weight: still a valid plan, at most
// that weight times the optimal (weight 1) cost; never at weight 1, nor with late_expansions 0.
TEST(HybridAStar, LateWeightHurriesOnlyLongSearches) {
  std::mt19937 rng(8);
  int hurried = 0, compared = 0;
  double worst = 0.0;
  for (int m = 0; m < 3; ++m) {
    const Grid2D map = test::random_map(rng, 60, 60, 30);
    PlannerConfig optimal, never, early;
    optimal.heuristic_weight = 1.0;
    optimal.late_expansions = 1;  // ignored at weight 1
    never.late_expansions = 0;
    early.late_expansions = 20;
    HybridAStar a(map, {}, optimal), b(map, {}, never), c(map, {}, early);
    std::uniform_real_distribution<double> pos(1.0, 59.0), yaw(-M_PI, M_PI);
    for (int q = 0; q < 4; ++q) {
      Pose2 s{pos(rng), pos(rng), yaw(rng)}, g{pos(rng), pos(rng), yaw(rng)};
      while (!a.map().pose_free(s)) s = {pos(rng), pos(rng), yaw(rng)};
      while (!a.map().pose_free(g)) g = {pos(rng), pos(rng), yaw(rng)};
      const PlanResult ra = a.plan(s, g), rb = b.plan(s, g), rc = c.plan(s, g);
      EXPECT_FALSE(ra.late_weight);
      EXPECT_FALSE(rb.late_weight);
      EXPECT_TRUE(rc.late_weight || rc.expansions <= 20) << rc.expansions;
      EXPECT_TRUE(!rc.late_weight || rc.expansions >= 20) << rc.expansions;
      EXPECT_EQ(ra.ok(), rc.ok()) << to_string(ra.status) << " " << to_string(rc.status);
      if (!ra.ok() || !rc.ok()) continue;
      hurried += rc.late_weight;
      ++compared;
      worst = std::max(worst, rc.cost / ra.cost);
      EXPECT_LE(rc.cost, early.late_heuristic_weight * ra.cost * (1.0 + 1e-9));
    }
  }
  std::printf("late weight: %d of %d plans hurried, cost at most %.3f x the optimal\n", hurried,
              compared, worst);
  EXPECT_GE(hurried, 4);
}

}  // namespace
}  // namespace fieldlidar::planning
