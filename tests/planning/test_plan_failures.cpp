// Typed failures: bad poses, absurd radii, a goal in a wall or off the map, a map of unknown
// cells, and budgets that are always respected.

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/planning/hybrid_astar.hpp"
#include "test_maps.hpp"

namespace fieldlidar::planning {
namespace {

using test::block;
using test::open_map;

TEST(PlanFailures, EachCauseHasItsStatus) {
  Grid2D map = open_map(30, 30);
  block(map, 14, 0, 16, 30);  // a wall across the map
  HybridAStar planner(map, {});
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(planner.plan({nan, 4, 0}, {20, 4, 0}).status, PlanStatus::kInvalidInput);
  EXPECT_EQ(planner.plan({4, 4, 0}, {20, 4, INFINITY}).status, PlanStatus::kInvalidInput);
  EXPECT_EQ(planner.plan({-5, 4, 0}, {20, 4, 0}).status, PlanStatus::kStartOffMap);
  EXPECT_EQ(planner.plan({4, 4, 0}, {20, 45, 0}).status, PlanStatus::kGoalOffMap);
  EXPECT_EQ(planner.plan({15, 4, 0}, {20, 4, 0}).status, PlanStatus::kStartInCollision);
  EXPECT_EQ(planner.plan({4, 4, 0}, {15, 20, 0}).status, PlanStatus::kGoalInCollision);
  EXPECT_EQ(planner.plan({4, 4, 0}, {13.8, 20, 0}).status, PlanStatus::kGoalInCollision);
  EXPECT_EQ(planner.plan({4, 4, 0}, {0.1, 20, 0}).status, PlanStatus::kGoalInCollision);
  EXPECT_EQ(planner.plan({4, 4, 0}, {25, 4, 0}).status, PlanStatus::kNoPath);
}

TEST(PlanFailures, AbsurdRadiiAndBudgetsAreInvalidInput) {
  const Grid2D map = open_map(20, 20);
  for (double r : {0.0, -1.0, 1e-6, 1e9, std::numeric_limits<double>::quiet_NaN()}) {
    PlannerConfig c;
    c.min_turn_radius_m = r;
    EXPECT_EQ(plan_path(map, {}, {4, 4, 0}, {15, 15, 0}, c).status, PlanStatus::kInvalidInput) << r;
  }
  PlannerConfig c;
  c.time_budget_ms = -1;
  EXPECT_EQ(plan_path(map, {}, {4, 4, 0}, {15, 15, 0}, c).status, PlanStatus::kInvalidInput);
  terrain::RobotConfig huge;
  huge.length_m = 1e6;
  EXPECT_THROW(HybridAStar(map, huge), Error);
  // Cells so fine that the footprint spans more than kMaxFootprintCells: refused before the
  // footprint masks (which grow with the square of that) are built.
  for (double res : {0.015, 1e-9}) {
    try {
      HybridAStar(open_map(40 * res, 40 * res, res), {});  // 40 x 40 cells
      FAIL() << res;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("cells across"), std::string::npos) << e.what();
    }
  }
  EXPECT_NO_THROW(HybridAStar(open_map(4, 4, 0.02), {}));
}

TEST(PlanFailures, AllUnknownMapIsTyped) {
  Grid2D map = open_map(20, 20);
  for (auto& v : map.layer(terrain::layer::kTraversability))
    v = std::numeric_limits<float>::quiet_NaN();
  for (auto& v : map.layer(terrain::layer::kPoints)) v = 0.0f;
  EXPECT_EQ(plan_path(map, {}, {4, 4, 0}, {15, 15, 0}).status, PlanStatus::kMapUnknown);
}

TEST(PlanFailures, UnknownCellsAreBlockedWhenNotAllowed) {
  Grid2D map = open_map(30, 10);
  auto tau = map.layer(terrain::layer::kTraversability);
  const GridGeometry& g = map.geometry();
  for (int iy = 0; iy < g.height; ++iy) tau[g.linear_index(30, iy)] = NAN;  // x in [15, 15.5)
  PlannerConfig c;
  EXPECT_TRUE(plan_path(map, {}, {4, 5, 0}, {26, 5, 0}, c).ok());
  c.map.allow_unknown = false;
  EXPECT_EQ(plan_path(map, {}, {4, 5, 0}, {26, 5, 0}, c).status, PlanStatus::kNoPath);
}

TEST(PlanFailures, BudgetsAreRespected) {
  // A large open map with a long wall: the search needs many expansions.
  Grid2D map = open_map(150, 150);
  block(map, 70, 0, 72, 140);
  PlannerConfig c;
  c.time_budget_ms = 2.0;
  c.smooth = false;
  HybridAStar planner(map, {}, c);
  const auto r = planner.plan({5, 5, 0}, {145, 5, M_PI});
  EXPECT_EQ(r.status, PlanStatus::kTimedOut);
  // The clock is read every 8 expansions and every 512 heuristic cells (~0.1 ms of work); the
  // slack covers a loaded machine's scheduling, not the planner.
  EXPECT_LT(r.search_ms, 2.0 + 100.0) << r.expansions << " expansions";
  PlannerConfig e = c;
  e.time_budget_ms = 10000;
  e.max_expansions = 50;
  const auto r2 = plan_path(map, {}, {5, 5, 0}, {145, 5, M_PI}, e);
  EXPECT_EQ(r2.status, PlanStatus::kExpansionLimit);
  EXPECT_EQ(r2.expansions, 50);
}

}  // namespace
}  // namespace fieldlidar::planning
