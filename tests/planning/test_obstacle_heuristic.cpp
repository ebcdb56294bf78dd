// The obstacle-aware heuristic settles cells towards the start first (reverse resumable A*):
// every cost it returns must be the one a plain Dijkstra from the goal gives, whatever the
// order in which cells are asked for, and a cell near the start must cost fewer settled cells.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "obstacle_heuristic.hpp"
#include "test_maps.hpp"

namespace fieldlidar::planning {
namespace {

TEST(ObstacleHeuristic, FocusedOrderGivesDijkstrasCosts) {
  const auto far = std::chrono::steady_clock::now() + std::chrono::hours(1);
  std::mt19937 rng(5);
  for (int trial = 0; trial < 4; ++trial) {
    const Grid2D grid = test::random_map(rng, 60.0, 40.0, 40);
    const PlanningMap map(grid, {}, {});
    const long n = long(map.geometry().cell_count());
    std::uniform_int_distribution<long> cell(0, n - 1);
    long goal = cell(rng), start = cell(rng);
    while (map.blocked(std::size_t(goal))) goal = cell(rng);
    while (map.blocked(std::size_t(start))) start = cell(rng);
    for (int downsample : {1, 2}) {
      ObstacleHeuristic dijkstra, focused;
      dijkstra.reset(map, goal, -1, 2.0, downsample);
      focused.reset(map, goal, start, 2.0, downsample);
      const double h_start = focused.cost_m(start, far);
      const std::size_t settled_for_start = focused.settled();
      EXPECT_NEAR(h_start, dijkstra.cost_m(start, far), 1e-4 * std::max(1.0, h_start));
      if (std::isfinite(h_start)) {
        EXPECT_LE(settled_for_start, dijkstra.settled());
      }
      // every cell, asked in a random order
      std::vector<long> order(std::size_t(n), 0);
      for (long i = 0; i < n; ++i) order[std::size_t(i)] = i;
      std::shuffle(order.begin(), order.end(), rng);
      int compared = 0;
      for (long i : order) {
        const double a = dijkstra.cost_m(i, far), b = focused.cost_m(i, far);
        if (std::isinf(a)) {
          EXPECT_TRUE(std::isinf(b)) << "cell " << i;
          continue;
        }
        ASSERT_NEAR(b, a, 1e-4 * std::max(1.0, a)) << "cell " << i << ", downsample " << downsample;
        ++compared;
      }
      EXPECT_GT(compared, n / 2);
    }
  }
}

}  // namespace
}  // namespace fieldlidar::planning
