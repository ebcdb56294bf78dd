// Property tests on random maps and queries: a returned path never puts the robot's exact
// footprint on an impassable cell, never bends tighter than R_min, and meets start and goal;
// every failure is a typed one and the time budget holds.

#include <cmath>
#include <cstdio>
#include <random>

#include <gtest/gtest.h>

#include "fieldlidar/planning/hybrid_astar.hpp"
#include "test_maps.hpp"

namespace fieldlidar::planning {
namespace {

TEST(PlanProperties, RandomMapsAndQueries) {
  std::mt19937 rng(4);
  int successes = 0, failures = 0, checked_samples = 0;
  double worst_kappa_ratio = 0.0;
  for (int m = 0; m < 8; ++m) {
    const Grid2D map = test::random_map(rng, 60, 60, 30);
    PlannerConfig c;
    c.min_turn_radius_m = m % 3 == 0 ? 2.0 : 1.0;
    c.time_budget_ms = 300;
    HybridAStar planner(map, {}, c);
    std::uniform_real_distribution<double> pos(1.0, 59.0), yaw(-M_PI, M_PI);
    auto free_pose = [&] {
      for (;;) {
        const Pose2 p{pos(rng), pos(rng), yaw(rng)};
        if (planner.map().pose_free(p)) return p;
      }
    };
    for (int q = 0; q < 4; ++q) {
      const Pose2 s = free_pose(), g = free_pose();
      const PlanResult r = planner.plan(s, g);
      // The deadline is checked between expansions and in the heuristic's Dijkstra; the margin
      // is for a loaded machine, where a descheduled process overruns any wall-clock deadline.
      EXPECT_LT(r.search_ms, 2.0 * c.time_budget_ms);
      if (!r.ok()) {
        ++failures;
        EXPECT_TRUE(r.status == PlanStatus::kNoPath || r.status == PlanStatus::kTimedOut)
            << to_string(r.status);
        EXPECT_TRUE(r.path.empty());
        continue;
      }
      ++successes;
      for (const Path* p : {&r.path, &r.raw_path}) {
        ASSERT_GE(p->size(), 2u);
        EXPECT_NEAR(p->front().pose.x_m, s.x_m, 1e-9);
        EXPECT_NEAR(p->front().pose.y_m, s.y_m, 1e-9);
        EXPECT_LE(std::hypot(p->back().pose.x_m - g.x_m, p->back().pose.y_m - g.y_m),
                  c.goal_xy_tolerance_m + 1e-9);
        EXPECT_LE(std::abs(wrap_angle(p->back().pose.yaw_rad - g.yaw_rad)),
                  c.goal_yaw_tolerance_rad + 1e-9);
        const double k = max_curvature(*p);
        worst_kappa_ratio = std::max(worst_kappa_ratio, k * c.min_turn_radius_m);
        EXPECT_LE(k, 1.0 / c.min_turn_radius_m * (1.0 + 1e-6));
        for (const auto& sample : *p) {
          ++checked_samples;
          ASSERT_FALSE(planner.map().footprint_hits_blocked(sample.pose, 0.0))
              << sample.pose.x_m << "," << sample.pose.y_m << "," << sample.pose.yaw_rad;
        }
        // between samples too: the exact footprint at 2 cm steps along the polyline
        for (std::size_t i = 1; i < p->size(); ++i) {
          const Pose2 a = (*p)[i - 1].pose, b = (*p)[i].pose;
          for (double t : {0.25, 0.5, 0.75}) {
            const Pose2 mid{a.x_m + t * (b.x_m - a.x_m), a.y_m + t * (b.y_m - a.y_m),
                            a.yaw_rad + t * wrap_angle(b.yaw_rad - a.yaw_rad)};
            ASSERT_FALSE(planner.map().footprint_hits_blocked(mid, 0.0));
          }
        }
      }
    }
  }
  RecordProperty("successes", successes);
  RecordProperty("failures", failures);
  RecordProperty("checked_samples", checked_samples);
  EXPECT_GE(successes, 14);  // of 32 queries (the rest: no_path or timed_out, typed)
  std::printf(
      "random queries: %d planned, %d failed (typed), %d samples checked, worst kappa R_min %.6f\n",
      successes, failures, checked_samples, worst_kappa_ratio);
  EXPECT_LE(worst_kappa_ratio, 1.0 + 1e-6);
}

}  // namespace
}  // namespace fieldlidar::planning
