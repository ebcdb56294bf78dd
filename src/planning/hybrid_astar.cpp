// Seed 004, step f: Hybrid A*. f1 start into the open list; f2 expand the least g + h; f3 the
// forward and reverse arcs at R_min, a child on a tau = 0 cell straight to the closed list (f31),
// the others to the open list (f32); f4 near the goal a Reeds–Shepp shot, kept only when
// collision-free (f41), then smoothing (f42).

#include "fieldlidar/planning/hybrid_astar.hpp"

#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <queue>
#include <vector>

#include "fieldlidar/planning/reeds_shepp.hpp"
#include "obstacle_heuristic.hpp"
#include "path_cost.hpp"
#include "shortcut.hpp"
#include "state_table.hpp"

namespace fieldlidar::planning {
namespace {

using Clock = std::chrono::steady_clock;
constexpr int kClosedByTau = -2;  // state_node_ value of a state closed by f31

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

bool finite(const Pose2& p) {
  return std::isfinite(p.x_m) && std::isfinite(p.y_m) && std::isfinite(p.yaw_rad);
}

// Pose after driving signed length s (m) on an arc of signed curvature k (1/m; 0 straight).
Pose2 drive(const Pose2& p, double k, double s) {
  if (k == 0.0)
    return {p.x_m + s * std::cos(p.yaw_rad), p.y_m + s * std::sin(p.yaw_rad), p.yaw_rad};
  const double yaw = p.yaw_rad + k * s;
  return {p.x_m + (std::sin(yaw) - std::sin(p.yaw_rad)) / k,
          p.y_m - (std::cos(yaw) - std::cos(p.yaw_rad)) / k, wrap_angle(yaw)};
}

bool config_valid(const PlannerConfig& c) {
  return std::isfinite(c.min_turn_radius_m) && c.min_turn_radius_m >= 0.1 &&
         c.min_turn_radius_m <= 100.0 && c.heading_bins >= 8 && c.heading_bins <= 720 &&
         std::isfinite(c.step_m) && c.step_m >= 0.0 && c.step_m <= 10.0 &&
         std::isfinite(c.lattice_cell_m) && c.lattice_cell_m >= 0.0 && c.lattice_cell_m <= 10.0 &&
         std::isfinite(c.time_budget_ms) && c.time_budget_ms > 0.0 && c.max_expansions > 0 &&
         c.tau_weight >= 0.0 && c.reverse_factor >= 1.0 && c.turn_factor >= 1.0 &&
         c.direction_change_penalty_m >= 0.0 && c.path_resolution_m > 0.0 &&
         c.goal_xy_tolerance_m >= 0.0 && c.goal_yaw_tolerance_rad >= 0.0 &&
         c.heuristic_downsample >= 1 && c.heuristic_downsample <= 16 && c.heuristic_weight >= 1.0 &&
         c.heuristic_weight <= 10.0 && c.late_expansions >= 0 && c.late_heuristic_weight >= 1.0 &&
         c.late_heuristic_weight <= 10.0;
}

struct Primitive {
  double curvature;  ///< 1/m, signed
  double length_m;   ///< signed: negative in reverse
  /// Poses along it in the frame of its start, at the footprint-check spacing; the last is its
  /// end (a pose in the map frame is then one rotation away: no trigonometry per sample).
  std::vector<Pose2> local;
};

// `local` (a pose relative to p, in p's frame) in the map frame, given cos and sin of p's yaw.
Pose2 compose(const Pose2& p, double c, double s, const Pose2& local) {
  double yaw = p.yaw_rad + local.yaw_rad;
  if (yaw > std::numbers::pi) yaw -= 2.0 * std::numbers::pi;
  if (yaw <= -std::numbers::pi) yaw += 2.0 * std::numbers::pi;
  return {p.x_m + c * local.x_m - s * local.y_m, p.y_m + s * local.x_m + c * local.y_m, yaw};
}

}  // namespace

struct HybridAStar::Search {
  struct Node {
    Pose2 pose;
    double g = 0.0;
    int parent = -1;
    int primitive = -1;  ///< index into primitives, -1 at the start
    std::uint32_t state = 0;
    bool closed = false;
    /// The Reeds–Shepp term is taken into h only when the node is first popped (it costs more
    /// than the rest of the heuristic, and most children are never expanded); h is then raised
    /// to it and the node queued again if it grew.
    bool rs_pending = false;
    double h = 0.0;
  };
  using Entry = std::pair<double, int>;
  static constexpr int kGoalEntry = -1;  ///< an open-list entry for the best goal candidate
  /// f = g + weight h; among equal f the deeper node (larger g) first.
  static double key(double g, double h, double weight) { return g + weight * h - 1e-6 * g; }
  std::vector<Node> nodes;
  StateTable state_node;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
  ObstacleHeuristic heuristic;

  /// The open list rebuilt with keys g + weight h (the goal candidate's cost, when >= 0, kept).
  void rekey(double weight, double goal_cost) {
    std::vector<Entry> entries;
    for (int i = 0; i < int(nodes.size()); ++i) {
      const Node& n = nodes[i];
      if (!n.closed && *state_node.find(n.state) == i)
        entries.push_back({key(n.g, n.h, weight), i});
    }
    if (goal_cost >= 0.0) entries.push_back({goal_cost, kGoalEntry});
    open = decltype(open)(std::greater<>(), std::move(entries));
  }
};

HybridAStar::HybridAStar(const Grid2D& map, const terrain::RobotConfig& robot, PlannerConfig config)
    : map_(map, robot, config.map),
      config_(std::move(config)),
      search_(std::make_unique<Search>()) {}
HybridAStar::~HybridAStar() = default;
HybridAStar::HybridAStar(HybridAStar&&) noexcept = default;
HybridAStar& HybridAStar::operator=(HybridAStar&&) noexcept = default;

PlanResult HybridAStar::plan(const Pose2& start_in, const Pose2& goal_in) {
  const auto t0 = Clock::now();
  PlanResult result;
  auto fail = [&](PlanStatus s) {
    result.status = s;
    result.search_ms = ms_since(t0);
    return result;
  };
  const PlannerConfig& c = config_;
  if (!finite(start_in) || !finite(goal_in) || !config_valid(c))
    return fail(PlanStatus::kInvalidInput);
  const Pose2 start{start_in.x_m, start_in.y_m, wrap_angle(start_in.yaw_rad)};
  const Pose2 goal{goal_in.x_m, goal_in.y_m, wrap_angle(goal_in.yaw_rad)};
  if (map_.known_cells() == 0) return fail(PlanStatus::kMapUnknown);
  const long start_cell = map_.cell_index(start.x_m, start.y_m);
  const long goal_cell = map_.cell_index(goal.x_m, goal.y_m);
  if (start_cell < 0) return fail(PlanStatus::kStartOffMap);
  if (goal_cell < 0) return fail(PlanStatus::kGoalOffMap);
  if (!map_.pose_free(start)) return fail(PlanStatus::kStartInCollision);
  if (!map_.pose_free(goal)) return fail(PlanStatus::kGoalInCollision);

  const double R = c.min_turn_radius_m;
  const auto& geo = map_.geometry();
  const double res = geo.resolution_m;
  const double lattice = c.lattice_cell_m > 0.0 ? c.lattice_cell_m : res;
  const long lattice_width = long(std::ceil(geo.width * res / lattice));
  const double lattice_cells = double(lattice_width) * std::ceil(geo.height * res / lattice);
  if (lattice_cells * c.heading_bins >= 4.0e9) return fail(PlanStatus::kInvalidInput);
  const double step = c.step_m > 0.0 ? c.step_m : lattice * std::numbers::sqrt2 * 1.05;
  const double check_step = std::min(0.5 * res, 0.25);  // footprint checks along an arc (m)
  const int bins = c.heading_bins;
  const double bin_rad = 2.0 * std::numbers::pi / bins;
  std::vector<Primitive> prims;
  for (double dir : {1.0, -1.0})
    for (double k : {0.0, 1.0 / R, -1.0 / R}) {
      Primitive m{k, dir * step, {}};
      const int n = std::max(1, int(std::ceil(step / check_step)));
      for (int i = 1; i <= n; ++i) m.local.push_back(drive({0, 0, 0}, k, m.length_m * i / n));
      prims.push_back(std::move(m));
    }

  auto state_of = [&](const Pose2& p, long cell) {
    int b = int(std::lround(p.yaw_rad / bin_rad)) % bins;
    if (b < 0) b += bins;
    if (lattice != res)  // the lattice cell holding p (p is on the map)
      cell = long((p.y_m - geo.origin_m.y()) / lattice) * lattice_width +
             long((p.x_m - geo.origin_m.x()) / lattice);
    return std::uint32_t(cell) * std::uint32_t(bins) + std::uint32_t(b);
  };
  auto cost_mult = [&](long cell) {
    return 1.0 + c.tau_weight * (1.0 - map_.tau(std::size_t(cell)));
  };

  Search& s = *search_;
  s.nodes.clear();
  s.state_node.clear();
  s.open = {};
  const auto th = Clock::now();
  const auto deadline = t0 + std::chrono::microseconds(long(c.time_budget_ms * 1000.0));
  s.heuristic.reset(map_, goal_cell, start_cell, c.tau_weight, c.heuristic_downsample);
  // h without the Reeds–Shepp term (the larger of the straight line and the obstacle-aware cost)
  auto heuristic = [&](const Pose2& p, long cell) {
    const auto t = Clock::now();
    const double obstacle = s.heuristic.cost_m(cell, deadline);
    result.heuristic_ms += ms_since(t);
    if (std::isnan(obstacle)) return obstacle;
    return std::max(std::hypot(goal.x_m - p.x_m, goal.y_m - p.y_m), obstacle);
  };
  auto rs_wanted = [&](const Pose2& p) {
    return std::hypot(goal.x_m - p.x_m, goal.y_m - p.y_m) < c.rs_heuristic_range_m;
  };
  result.heuristic_ms += ms_since(th);
  double h_start = heuristic(start, start_cell);
  if (std::isnan(h_start)) return fail(PlanStatus::kTimedOut);
  if (!std::isfinite(h_start)) return fail(PlanStatus::kNoPath);
  if (rs_wanted(start)) h_start = std::max(h_start, reeds_shepp_length_m(start, goal, R));

  s.nodes.push_back({start, 0.0, -1, -1, state_of(start, start_cell), false, false, h_start});
  s.state_node.set(s.nodes[0].state, 0);
  s.open.push({h_start, 0});

  // The cost of driving a sampled curve from node `from` (the same terms as the primitives).
  const PathCostTerms terms{c.tau_weight, c.reverse_factor, c.turn_factor,
                            c.direction_change_penalty_m};
  auto curve_cost = [&](int from, const Path& samples) {
    double cost = 0.0;
    bool prev_reverse = s.nodes[from].primitive >= 0 && prims[s.nodes[from].primitive].length_m < 0;
    bool has_prev = s.nodes[from].primitive >= 0;
    for (std::size_t k = 1; k < samples.size(); ++k) {
      cost += step_cost(map_, terms, samples[k - 1], samples[k]);
      if (has_prev && samples[k].reverse != prev_reverse) cost += c.direction_change_penalty_m;
      prev_reverse = samples[k].reverse;
      has_prev = true;
    }
    return cost;
  };

  // A collision-free shot is a goal candidate in the open list at its true cost (so a cheaper
  // way round low-tau ground can still win); the search ends when a candidate is popped.
  constexpr int kGoalEntry = Search::kGoalEntry;
  int goal_node = -1, best_shot_node = -1;
  double best_goal_g = std::numeric_limits<double>::infinity();
  RsCurve shot, best_shot;
  int since_shot = 0;
  double weight = c.heuristic_weight;
  while (!s.open.empty()) {
    if (c.late_expansions > 0 && result.expansions == c.late_expansions && weight > 1.0 &&
        c.late_heuristic_weight > weight) {
      weight = c.late_heuristic_weight;
      result.late_weight = true;
      s.rekey(weight, best_shot_node >= 0 ? best_goal_g : -1.0);
    }
    if ((result.expansions & 7) == 0 && Clock::now() > deadline) return fail(PlanStatus::kTimedOut);
    if (result.expansions >= c.max_expansions) return fail(PlanStatus::kExpansionLimit);
    const auto [f_top, idx] = s.open.top();
    s.open.pop();
    if (idx == kGoalEntry) {
      if (f_top != best_goal_g) continue;
      goal_node = best_shot_node;
      shot = best_shot;
      result.reached_by_shot = true;
      break;
    }
    if (s.nodes[idx].closed || *s.state_node.find(s.nodes[idx].state) != idx) continue;  // stale
    if (s.nodes[idx].rs_pending) {
      auto& node = s.nodes[idx];
      node.rs_pending = false;
      // the solver only when its cheap upper bound could raise h
      const double rs = reeds_shepp_upper_bound_m(node.pose, goal, R) <= node.h
                            ? node.h
                            : reeds_shepp_length_m(node.pose, goal, R);
      if (rs > node.h) {
        node.h = rs;
        s.open.push({Search::key(node.g, node.h, weight), idx});
        continue;
      }
    }
    s.nodes[idx].closed = true;
    ++result.expansions;
    if (s.nodes[idx].g + 1e-9 >= best_goal_g) continue;  // cannot beat the candidate
    const Pose2 p = s.nodes[idx].pose;
    const double d_goal = std::hypot(goal.x_m - p.x_m, goal.y_m - p.y_m);
    if (d_goal <= c.goal_xy_tolerance_m &&
        std::abs(wrap_angle(goal.yaw_rad - p.yaw_rad)) <= c.goal_yaw_tolerance_rad) {
      goal_node = idx;
      break;
    }
    // f4: a Reeds–Shepp shot, tried more often the closer the node is to the goal.
    if (d_goal < c.shot_distance_m && ++since_shot >= std::max(1, int(d_goal / 2.0))) {
      since_shot = 0;
      ++result.shots_tried;
      const RsCurve curve = reeds_shepp(p, goal, R);
      const Path samples = rs_sample(p, curve, R, check_step);
      if (samples_free(samples, map_)) {  // f41 otherwise: back to f2
        const double g = s.nodes[idx].g + curve_cost(idx, samples);
        if (g < best_goal_g) {
          best_goal_g = g;
          best_shot_node = idx;
          best_shot = curve;
          s.open.push({g, kGoalEntry});
        }
      }
    }
    // f3: children along the primitives.
    const int parent_prim = s.nodes[idx].primitive;
    const double cy = std::cos(p.yaw_rad), sy = std::sin(p.yaw_rad);
    for (int pi = 0; pi < int(prims.size()); ++pi) {
      const Primitive& m = prims[pi];
      const Pose2 q = compose(p, cy, sy, m.local.back());
      const long cell = map_.cell_index(q.x_m, q.y_m);
      if (cell < 0) continue;
      const std::uint32_t st = state_of(q, cell);
      if (st == s.nodes[idx].state) continue;
      const std::int32_t* known = s.state_node.find(st);
      if (known && (*known == kClosedByTau || s.nodes[*known].closed)) continue;
      if (map_.blocked(std::size_t(cell))) {  // f31
        s.state_node.set(st, kClosedByTau);
        continue;
      }
      bool free = map_.pose_free(q);
      for (std::size_t k = 0; k + 1 < m.local.size() && free; ++k)
        free = map_.pose_free(compose(p, cy, sy, m.local[k]));
      if (!free) continue;
      const bool reverse = m.length_m < 0;
      double g = s.nodes[idx].g + std::abs(m.length_m) * cost_mult(cell) *
                                      (reverse ? c.reverse_factor : 1.0) *
                                      (m.curvature != 0.0 ? c.turn_factor : 1.0);
      if (parent_prim >= 0 && (prims[parent_prim].length_m < 0) != reverse)
        g += c.direction_change_penalty_m;
      if (known && s.nodes[*known].g <= g) continue;
      const double h = heuristic(q, cell);
      if (std::isnan(h)) return fail(PlanStatus::kTimedOut);
      if (!std::isfinite(h)) continue;
      s.nodes.push_back({q, g, idx, pi, st, false, rs_wanted(q), h});
      const int child = int(s.nodes.size()) - 1;
      s.state_node.set(st, child);
      s.open.push({Search::key(g, h, weight), child});  // f32
    }
  }
  if (goal_node < 0) return fail(PlanStatus::kNoPath);

  // The path: each primitive re-sampled at path_resolution_m, then the shot.
  std::vector<int> chain;
  for (int i = goal_node; i >= 0; i = s.nodes[i].parent) chain.push_back(i);
  Path raw{{start, false}};
  for (auto it = chain.rbegin() + 1; it < chain.rend(); ++it) {
    const auto& node = s.nodes[*it];
    const Primitive& m = prims[node.primitive];
    const Pose2& from = s.nodes[node.parent].pose;
    const int n = std::max(1, int(std::ceil(std::abs(m.length_m) / c.path_resolution_m)));
    for (int k = 1; k <= n; ++k)
      raw.push_back(
          {k == n ? node.pose : drive(from, m.curvature, m.length_m * k / n), m.length_m < 0});
  }
  result.cost = s.nodes[goal_node].g;
  if (result.reached_by_shot) {
    const Path tail = rs_sample(s.nodes[goal_node].pose, shot, R, c.path_resolution_m);
    for (std::size_t k = 1; k < tail.size(); ++k) raw.push_back(tail[k]);
    raw.back().pose = goal;
    result.cost = best_goal_g;
  }
  if (raw.size() > 1) raw[0].reverse = raw[1].reverse;
  result.search_ms = ms_since(t0);
  result.raw_path = raw;
  const auto tc = Clock::now();
  if (c.shortcut) {
    ShortcutConfig scc;
    scc.radius_m = R;
    scc.resolution_m = c.path_resolution_m;
    scc.cost = terms;
    ShortcutReport report;
    raw = shortcut_path(raw, map_, scc, &report);
    result.shortcuts = report.replaced;
  }
  result.shortcut_ms = ms_since(tc);
  const auto ts = Clock::now();
  SmoothingConfig sc = c.smoothing;
  sc.tau_weight = c.tau_weight;
  result.path = c.smooth ? smooth_path(raw, map_, 1.0 / R, sc, &result.smoothing) : raw;
  result.smooth_ms = ms_since(ts);
  result.status = PlanStatus::kSuccess;
  return result;
}

PlanResult plan_path(const Grid2D& map, const terrain::RobotConfig& robot, const Pose2& start,
                     const Pose2& goal, const PlannerConfig& config) {
  HybridAStar planner(map, robot, config);
  return planner.plan(start, goal);
}

}  // namespace fieldlidar::planning
