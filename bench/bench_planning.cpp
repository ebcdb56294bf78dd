// Hybrid A* on a 384 x 384 map of 0.5 m cells (147k cells, synthetic rocks and walls, tau
// varying): median and p95 time and expansions per plan over random queries; side by side,
// OMPL's RRT* and BIT* in the Reeds–Shepp space with the same footprint check and a 1 s budget
// on the same queries (path length ratio and time ratio in the same run; OMPL's random seed is
// fixed so runs compare).

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <random>
#include <vector>

#include <benchmark/benchmark.h>
#include <ompl/base/ScopedState.h>
#include <ompl/base/objectives/PathLengthOptimizationObjective.h>
#include <ompl/base/spaces/ReedsSheppStateSpace.h>
#include <ompl/geometric/SimpleSetup.h>
#include <ompl/geometric/planners/informedtrees/BITstar.h>
#include <ompl/geometric/planners/rrt/RRTstar.h>
#include <ompl/util/Console.h>
#include <ompl/util/RandomNumbers.h>

#include "fieldlidar/planning/hybrid_astar.hpp"
#include "fieldlidar/planning/path_check.hpp"
#include "planning_timing.hpp"

namespace {

using namespace fieldlidar;
using namespace fieldlidar::planning;
using fieldlidar::bench::percentile;
using fieldlidar::bench::thread_cpu_ms;
namespace L = terrain::layer;

Grid2D bench_map(std::uint32_t seed) {
  GridGeometry g;
  g.resolution_m = 0.5;
  g.width = g.height = 384;
  Grid2D map(g);
  auto tau = map.add_layer(L::kTraversability, 1.0f);
  auto imp = map.add_layer(L::kImpassable, 0.0f);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 192.0), r(0.5, 3.0), ph(0.0, 6.3);
  // tau varies smoothly as on real ground (slopes and rough patches several metres across), in
  // [0.3, 1]
  const double p1 = ph(rng), p2 = ph(rng), p3 = ph(rng);
  for (int iy = 0; iy < 384; ++iy)
    for (int ix = 0; ix < 384; ++ix) {
      const double x = ix * 0.5, y = iy * 0.5;
      const double v =
          std::sin(x / 9.0 + p1) * std::cos(y / 7.0 + p2) + 0.5 * std::sin((x + y) / 4.0 + p3);
      tau[g.linear_index(ix, iy)] = float(std::clamp(0.75 + 0.25 * v, 0.3, 1.0));
    }
  auto blockc = [&](double cx, double cy, double rad) {
    for (int iy = std::max(0, int((cy - rad) / 0.5)); iy < std::min(384, int((cy + rad) / 0.5) + 1);
         ++iy)
      for (int ix = std::max(0, int((cx - rad) / 0.5));
           ix < std::min(384, int((cx + rad) / 0.5) + 1); ++ix)
        if (std::hypot((ix + 0.5) * 0.5 - cx, (iy + 0.5) * 0.5 - cy) < rad) {
          tau[g.linear_index(ix, iy)] = 0.0f;
          imp[g.linear_index(ix, iy)] = 1.0f;
        }
  };
  for (int k = 0; k < 250; ++k) blockc(u(rng), u(rng), r(rng));  // rock fields
  for (int k = 0; k < 12; ++k) {                                 // walls (ditches)
    const double x = u(rng), y = u(rng), a = u(rng);
    for (double s = 0; s < 25; s += 0.25) blockc(x + s * std::cos(a), y + s * std::sin(a), 0.5);
  }
  return map;
}

struct Query {
  Pose2 start, goal;
};

std::vector<Query> queries(const HybridAStar& planner, int n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(5.0, 187.0), yaw(-M_PI, M_PI);
  std::vector<Query> q;
  while (int(q.size()) < n) {
    const Pose2 a{u(rng), u(rng), yaw(rng)}, b{u(rng), u(rng), yaw(rng)};
    const double d = std::hypot(a.x_m - b.x_m, a.y_m - b.y_m);
    if (d < 20.0 || d > 80.0) continue;  // typical: 20-80 m apart
    if (planner.map().pose_free(a) && planner.map().pose_free(b)) q.push_back({a, b});
  }
  return q;
}

// Direction changes of an OMPL Reeds–Shepp path (between and within its segments).
int cusps(const ompl::geometric::PathGeometric& path) {
  const auto* space =
      path.getSpaceInformation()->getStateSpace()->as<ompl::base::ReedsSheppStateSpace>();
  int n = 0, last = 0;
  for (std::size_t i = 1; i < path.getStateCount(); ++i) {
    const auto rs = space->reedsShepp(path.getState(i - 1), path.getState(i));
    for (double l : rs.length_) {
      const int sign = l > 1e-9 ? 1 : (l < -1e-9 ? -1 : 0);
      if (sign != 0 && last != 0 && sign != last) ++n;
      if (sign != 0) last = sign;
    }
  }
  return n;
}

void BM_HybridAStar147k(benchmark::State& state) {
  const Grid2D map = bench_map(7);
  PlannerConfig c;
  c.smooth = state.range(0) != 0;
  c.heuristic_weight = state.range(1) / 10.0;
  c.heuristic_downsample = int(state.range(2));
  HybridAStar planner(map, {}, c);
  PlannerConfig c1 = c;  // the reference: w = 1, full-resolution heuristic
  c1.heuristic_weight = 1.0;
  c1.heuristic_downsample = 1;
  HybridAStar reference(map, {}, c1);
  // The cost of a returned (shortcut and smoothed) path, as the search counts it but turning
  auto path_cost = [&](const Path& p) {
    double sum = c.direction_change_penalty_m * direction_changes(p);
    for (double step : path_step_costs(planner.map(), p, c.tau_weight, c.reverse_factor))
      sum += step;
    return sum;
  };
  std::vector<double> final_ratio, cost_ratio, shorter_pct, straighter_pct;
  int smoothed = 0;
  const auto qs = queries(planner, 60, 11);
  std::vector<double> ms, search_ms, shortcut_ms, smooth_ms, exp, cpu_ms, heuristic_ms;
  int ok = 0, nopath = 0, timed_out = 0, other = 0, late = 0;
  for (auto _ : state) {
    ms.clear();
    for (const auto& q : qs) {
      const double c0 = thread_cpu_ms();
      const auto r = planner.plan(q.start, q.goal);
      const double cpu = thread_cpu_ms() - c0;
      if (r.ok()) {
        ++ok;
        cpu_ms.push_back(cpu);
        if (c.smooth) {
          smoothed += r.smoothing.blend > 0.0;
          shorter_pct.push_back(100.0 *
                                (1.0 - r.smoothing.length_after_m / r.smoothing.length_before_m));
          straighter_pct.push_back(
              100.0 * (1.0 - r.smoothing.turning_after_rad / r.smoothing.turning_before_rad));
        }
        const auto r1 = reference.plan(q.start, q.goal);
        if (r1.ok()) {
          cost_ratio.push_back(r.cost / r1.cost);
          final_ratio.push_back(path_cost(r.path) / path_cost(r1.path));
        }
        ms.push_back(r.search_ms + r.shortcut_ms + r.smooth_ms);
        search_ms.push_back(r.search_ms);
        heuristic_ms.push_back(r.heuristic_ms);
        shortcut_ms.push_back(r.shortcut_ms);
        smooth_ms.push_back(r.smooth_ms);
        exp.push_back(r.expansions);
        late += r.late_weight;
        if (std::getenv("FIELDLIDAR_BENCH_DETAIL"))
          std::fprintf(stderr,
                       "query %d: %.2f ms CPU (search %.2f, heuristic %.2f, shortcut %.2f, "
                       "smoothing %.2f), %d expansions, %d shots, %.1f m apart, cost %.2f\n",
                       int(&q - qs.data()), cpu, r.search_ms, r.heuristic_ms, r.shortcut_ms,
                       r.smooth_ms, r.expansions, r.shots_tried,
                       std::hypot(q.goal.x_m - q.start.x_m, q.goal.y_m - q.start.y_m), r.cost);
      } else if (r.status == PlanStatus::kNoPath) {
        ++nopath;
      } else if (r.status == PlanStatus::kTimedOut) {
        ++timed_out;
      } else {
        ++other;
      }
    }
  }
  state.counters["cpu_median_ms"] = percentile(cpu_ms, 0.5);
  state.counters["cpu_p95_ms"] = percentile(cpu_ms, 0.95);
  state.counters["median_ms"] = percentile(ms, 0.5);
  state.counters["p95_ms"] = percentile(ms, 0.95);
  state.counters["search_median_ms"] = percentile(search_ms, 0.5);
  state.counters["search_p95_ms"] = percentile(search_ms, 0.95);
  state.counters["heuristic_median_ms"] = percentile(heuristic_ms, 0.5);
  state.counters["shortcut_median_ms"] = percentile(shortcut_ms, 0.5);
  state.counters["smooth_median_ms"] = percentile(smooth_ms, 0.5);
  state.counters["smooth_p95_ms"] = percentile(smooth_ms, 0.95);
  state.counters["expansions_median"] = percentile(exp, 0.5);
  state.counters["expansions_p95"] = percentile(exp, 0.95);
  state.counters["planned"] = ok;
  state.counters["no_path"] = nopath;
  state.counters["timed_out"] = timed_out;
  if (c.smooth) {
    state.counters["smoothed_plans"] = smoothed;
    state.counters["shorter_pct_median"] = percentile(shorter_pct, 0.5);
    state.counters["shorter_pct_max"] = percentile(shorter_pct, 1.0);
    state.counters["turning_less_pct_median"] = percentile(straighter_pct, 0.5);
    state.counters["turning_less_pct_max"] = percentile(straighter_pct, 1.0);
  }
  state.counters["cost_vs_w1_median"] = percentile(cost_ratio, 0.5);
  state.counters["cost_vs_w1_max"] = percentile(cost_ratio, 1.0);
  state.counters["other_failures"] = other;
  state.counters["late_weight_plans"] = late;  // searches hurried past late_expansions
  state.counters["final_cost_vs_w1_median"] = percentile(final_ratio, 0.5);
  state.counters["final_cost_vs_w1_p95"] = percentile(final_ratio, 0.95);
  state.counters["final_cost_vs_w1_max"] = percentile(final_ratio, 1.0);
}
BENCHMARK(BM_HybridAStar147k)
    ->ArgNames({"smooth", "weight_x10", "downsample"})
    ->Args({0, 10, 1})
    ->Args({0, 12, 1})
    ->Args({1, 12, 1})
    ->Args({0, 12, 2})
    ->Args({1, 12, 2})
    ->Args({0, 15, 2})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

// OMPL RRT* or BIT* (Reeds–Shepp space, the planner's own footprint check as the validity
// checker, 1 s of CPU) against Hybrid A* on the same 16 queries: length and time ratios. Our
// planner runs with tau out of its cost, and either its own reversing and turning costs or
// (length_only) none, which is OMPL's objective exactly.
void BM_RrtStarVsHybridAStar(benchmark::State& state) {
  ompl::msg::setLogLevel(ompl::msg::LOG_NONE);
  static const bool seeded = [] {
    ompl::RNG::setSeed(5);
    return true;
  }();
  (void)seeded;
  const bool bit_star = state.range(1) != 0;
  const Grid2D map = bench_map(7);
  PlannerConfig c;
  c.tau_weight = 0.0;  // tau does not enter: length, as for OMPL
  c.heuristic_weight = state.range(0) / 10.0;
  if (state.range(2) != 0) {  // exactly OMPL's objective: reversing and turning cost no more
    c.reverse_factor = 1.0;
    c.direction_change_penalty_m = 0.0;
    c.turn_factor = 1.0;
  }
  HybridAStar planner(map, {}, c);
  const auto qs = queries(planner, 16, 23);
  std::vector<double> len_ratio, simplified_ratio, time_ratio;
  int ompl_solved = 0, both = 0;
  for (auto _ : state) {
    for (const auto& q : qs) {
      const double c0 = thread_cpu_ms();
      const auto r = planner.plan(q.start, q.goal);
      const double ours_ms = thread_cpu_ms() - c0;
      auto space = std::make_shared<ompl::base::ReedsSheppStateSpace>(c.min_turn_radius_m);
      ompl::base::RealVectorBounds bounds(2);
      bounds.setLow(0.0);
      bounds.setHigh(192.0);
      space->setBounds(bounds);
      ompl::geometric::SimpleSetup ss(space);
      const PlanningMap& pm = planner.map();
      ss.setStateValidityChecker([&pm](const ompl::base::State* s) {
        const auto* se2 = s->as<ompl::base::SE2StateSpace::StateType>();
        return pm.pose_free({se2->getX(), se2->getY(), se2->getYaw()});
      });
      ss.getSpaceInformation()->setStateValidityCheckingResolution(0.25 / 192.0 / 1.5);
      ompl::base::ScopedState<ompl::base::SE2StateSpace> a(space), b(space);
      a->setXY(q.start.x_m, q.start.y_m);
      a->setYaw(q.start.yaw_rad);
      b->setXY(q.goal.x_m, q.goal.y_m);
      b->setYaw(q.goal.yaw_rad);
      ss.setStartAndGoalStates(a, b, 0.2);
      if (bit_star)
        ss.setPlanner(std::make_shared<ompl::geometric::BITstar>(ss.getSpaceInformation()));
      else
        ss.setPlanner(std::make_shared<ompl::geometric::RRTstar>(ss.getSpaceInformation()));
      ss.getProblemDefinition()->setOptimizationObjective(
          std::make_shared<ompl::base::PathLengthOptimizationObjective>(ss.getSpaceInformation()));
      // The budget is 1 s of this thread's CPU time, so a loaded machine does not starve OMPL.
      const double o0 = thread_cpu_ms();
      const auto solved = ss.solve(
          ompl::base::PlannerTerminationCondition([o0] { return thread_cpu_ms() - o0 >= 1000.0; }));
      const double ompl_ms = thread_cpu_ms() - o0;
      const bool exact = solved == ompl::base::PlannerStatus::EXACT_SOLUTION;
      ompl_solved += exact;
      if (exact && r.ok()) {
        ++both;
        const double ours = path_length_m(r.path), theirs = ss.getSolutionPath().length();
        len_ratio.push_back(ours / theirs);
        time_ratio.push_back(ompl_ms / ours_ms);
        // OMPL's own shortcutting on top (another 0.25 s of CPU), for a stricter comparison
        const double s0 = thread_cpu_ms();
        ss.simplifySolution(ompl::base::PlannerTerminationCondition(
            [s0] { return thread_cpu_ms() - s0 >= 250.0; }));
        const double simplified = ss.getSolutionPath().length();
        simplified_ratio.push_back(ours / simplified);
        if (std::getenv("FIELDLIDAR_BENCH_DETAIL"))
          std::fprintf(stderr,
                       "query %d: ours %.2f m (raw %.2f, %d shortcuts, %d direction changes, "
                       "%.1f ms), OMPL %.2f m, simplified %.2f m (%d changes)\n",
                       int(&q - qs.data()), ours, path_length_m(r.raw_path), r.shortcuts,
                       direction_changes(r.path), ours_ms, theirs, simplified,
                       cusps(ss.getSolutionPath()));
      }
    }
  }
  state.counters["queries"] = double(qs.size());
  state.counters["ompl_solved"] = ompl_solved;
  state.counters["both_solved"] = both;
  state.counters["length_ratio_median"] = percentile(len_ratio, 0.5);  // ours / OMPL's
  state.counters["length_ratio_max"] = percentile(len_ratio, 1.0);
  state.counters["length_ratio_p75"] = percentile(len_ratio, 0.75);
  state.counters["longer_than_ompl"] =
      double(std::count_if(len_ratio.begin(), len_ratio.end(), [](double x) { return x > 1.0; }));
  state.counters["simplified_length_ratio_median"] = percentile(simplified_ratio, 0.5);
  state.counters["simplified_length_ratio_max"] = percentile(simplified_ratio, 1.0);
  state.counters["time_ratio_median"] = percentile(time_ratio, 0.5);  // OMPL's / ours, CPU
  state.counters["time_ratio_min"] = percentile(time_ratio, 0.0);
}
BENCHMARK(BM_RrtStarVsHybridAStar)
    ->ArgNames({"weight_x10", "bit_star", "length_only"})
    ->Args({12, 0, 0})
    ->Args({12, 1, 0})
    ->Args({12, 0, 1})
    ->Args({12, 1, 1})
    ->Args({10, 0, 1})
    ->Args({10, 1, 1})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

}  // namespace
