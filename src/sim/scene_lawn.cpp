// The lawn scene of seed 000: a mower follows an operator walking the lawn's outline.

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "fieldlidar/sim/scenes.hpp"

namespace fieldlidar::sim {

namespace {

struct LawnShape {
  double length, width, bulge;
  /// y of the curved far edge at x (the lawn is 0 <= y <= top(x) for 0 <= x <= length).
  double top(double x) const {
    return width + bulge * std::sin(std::numbers::pi * std::clamp(x / length, 0.0, 1.0));
  }
  bool inside(double x, double y) const { return x >= 0 && x <= length && y >= 0 && y <= top(x); }
};

/// The operator's closed outline, `inset` inside the lawn edge: straight near edge and side edges
/// with right-angle corners, the curved far edge sampled every ~1 m.
std::vector<Eigen::Vector2d> outline(const LawnShape& lawn, double inset) {
  std::vector<Eigen::Vector2d> p;
  const double x0 = inset, x1 = lawn.length - inset;
  p.emplace_back(x0, inset);
  p.emplace_back(x1, inset);
  const int n = std::max(8, static_cast<int>((x1 - x0) / 1.0));
  for (int i = 0; i <= n; ++i) {
    const double x = x1 - (x1 - x0) * i / n;
    p.emplace_back(x, lawn.top(x) - inset);
  }
  return p;
}

Walker make_operator(const LawnConfig& cfg, std::vector<Eigen::Vector2d> path) {
  WalkerConfig w;
  w.id = 1;
  w.path_m = std::move(path);
  w.closed = true;
  w.start_offset_m = cfg.operator_start_m;
  const double v = cfg.operator_speed_m_s;
  std::vector<SpeedPhase> phases = {{0.0, v}};
  if (cfg.operator_waits_at_start) phases = {{0.0, 0.0}, {cfg.wait_at_start_s, v}};
  if (cfg.operator_stops) {
    phases.push_back({cfg.stop_time_s, 0.0});
    phases.push_back({cfg.stop_time_s + cfg.stop_duration_s, v});
  }
  if (cfg.operator_too_fast) {
    phases.push_back({cfg.fast_time_s, cfg.fast_speed_m_s});
    phases.push_back({cfg.fast_time_s + cfg.fast_duration_s, v});
  }
  w.speed = phases;
  w.height_m = 1.78;
  return Walker(std::move(w));
}

}  // namespace

Scene make_lawn_scene(const LawnConfig& cfg, std::uint64_t seed) {
  std::mt19937_64 rng(seed * 7919 + 1);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  const LawnShape lawn{cfg.length_m, cfg.width_m, 3.0};
  const double ph1 = 2 * std::numbers::pi * uni(rng), ph2 = 2 * std::numbers::pi * uni(rng),
               ph3 = 2 * std::numbers::pi * uni(rng);
  const double a = cfg.undulation_m;
  // The bumps' phases from a generator of their own: the rest of the scene stays as without.
  std::mt19937_64 bump_rng(seed * 7919 + 2);
  const double pb1 = 2 * std::numbers::pi * uni(bump_rng),
               pb2 = 2 * std::numbers::pi * uni(bump_rng),
               pb3 = 2 * std::numbers::pi * uni(bump_rng);
  // Gentle waves (wavelengths 18-40 m), short bumps, and a 4 cm drop from the mown lawn to its
  // surroundings.
  const auto height = [&](double x, double y) {
    const double wave = a * (0.6 * std::sin(0.35 * x + ph1) * std::cos(0.28 * y + ph2) +
                             0.4 * std::sin(0.15 * x + 0.2 * y + ph3));
    const double bumps =
        cfg.roughness_m > 0
            ? cfg.roughness_m * (0.6 * std::sin(2.4 * x + pb1) * std::cos(2.1 * y + pb2) +
                                 0.4 * std::sin(1.7 * x - 2.9 * y + pb3))
            : 0.0;
    return wave + bumps - (lawn.inside(x, y) ? 0.0 : 0.04);
  };
  const Eigen::Vector2d min(-8.0, -8.0), max(cfg.length_m + 10.0, cfg.width_m + 3.0 + 8.0);
  Scene scene(SceneKind::kLawn, HeightField(min, max, 0.25, height), seed);
  scene.set_sensor_height_m(0.45);
  scene.set_robot_speed_m_s(cfg.operator_speed_m_s);
  const auto structure = make_label(LabelClass::kStructure);
  const auto vegetation = make_label(LabelClass::kVegetation);

  // Shed beside the right edge: walls and a gable roof (m).
  const Eigen::Vector2d shed(cfg.length_m + 3.0, 0.35 * cfg.width_m);
  const double gz = scene.ground_height_at(shed);
  scene.add_mesh(make_aabb({shed.x() - 1.5, shed.y() - 1.25, gz - 0.1},
                           {shed.x() + 1.5, shed.y() + 1.25, gz + 2.1}, structure));
  for (int side : {-1, 1}) {
    Pose T = Pose::Identity();
    T.translation() = Eigen::Vector3d(shed.x(), shed.y() + side * 0.7, gz + 2.45);
    T.linear() = Eigen::AngleAxisd(side * 0.5, Eigen::Vector3d::UnitX()).toRotationMatrix();
    scene.add_mesh(make_box(T, {3.4, 1.6, 0.06}, structure));
  }

  // Hedge along the near side: overlapping rough blobs, ~1.3 m tall.
  for (double x = -3.0; x <= cfg.length_m + 1.0; x += 0.9) {
    const Eigen::Vector2d c(x, -2.0 + 0.15 * (uni(rng) - 0.5));
    const double z = scene.ground_height_at(c);
    scene.add_mesh(make_blob({c.x(), c.y(), z + 0.65}, {0.65, 0.5, 0.7}, 0.15, rng, vegetation));
  }
  // A flower bed along part of the curved edge and two garden trees.
  for (double x = 4.0; x <= cfg.length_m - 4.0; x += 1.4) {
    const Eigen::Vector2d c(x, lawn.top(x) + 1.0);
    scene.add_mesh(make_blob({c.x(), c.y(), scene.ground_height_at(c) + 0.2}, {0.45, 0.4, 0.3},
                             0.25, rng, vegetation));
  }
  std::uint16_t tree_id = 1;
  for (const Eigen::Vector2d& c : {Eigen::Vector2d(-4.0, cfg.width_m + 4.0),
                                   Eigen::Vector2d(cfg.length_m + 5.0, cfg.width_m + 2.0)}) {
    const double z = scene.ground_height_at(c);
    TreeTruth t;
    t.id = tree_id++;
    t.base_m = {c.x(), c.y(), z};
    t.dbh_m = 0.25 + 0.15 * uni(rng);
    t.height_m = 4.0;
    scene.add_tree(t);
    scene.add_mesh(make_cylinder(t.base_m - Eigen::Vector3d(0, 0, 0.2),
                                 t.base_m + Eigen::Vector3d(0, 0, 4.0), t.dbh_m / 2,
                                 t.dbh_m / 2 * 0.8, 24, make_label(LabelClass::kTrunk, t.id)));
    scene.add_mesh(
        make_blob(t.base_m + Eigen::Vector3d(0, 0, 5.0), {2.2, 2.2, 1.8}, 0.2, rng, vegetation));
  }

  // The operator (person 1) walks the outline, optionally detouring behind the shed.
  auto path = outline(lawn, cfg.edge_inset_m);
  if (cfg.operator_behind_shed) {
    const double xr = cfg.length_m - cfg.edge_inset_m, xb = shed.x() + 2.6;
    const std::vector<Eigen::Vector2d> detour = {
        {xr, shed.y() - 2.6}, {xb, shed.y() - 2.6}, {xb, shed.y() + 2.6}, {xr, shed.y() + 2.6}};
    path.insert(path.begin() + 2, detour.begin(), detour.end());
  }
  if (cfg.posts_near_start) {
    const Eigen::Vector2d dir = (path[1] - path[0]).normalized();
    const Eigen::Vector2d right(dir.y(), -dir.x());
    const Eigen::Vector2d c = path[0] + cfg.posts_ahead_m * dir + cfg.posts_right_m * right;
    for (double side : {-0.125, 0.125}) {
      const Eigen::Vector2d p = c + side * dir;
      const double z = scene.ground_height_at(p);
      scene.add_mesh(make_cylinder({p.x(), p.y(), z - 0.1}, {p.x(), p.y(), z + 1.0}, 0.06, 0.06, 16,
                                   structure));
    }
  }
  scene.set_operator_path(path);
  scene.set_robot_route(path, true);
  const Walker op = make_operator(cfg, path);
  scene.add_walker(op);

  std::uint16_t next_id = 2;
  if (cfg.second_person_crossing) {
    // Comes from the lawn's interior (the outline runs counter-clockwise, so left is inwards),
    // crosses the operator's path 2 m ahead of them at crossing_time_s at 1.2 m/s, then walks on
    // along the edge, between the path and the lawn's border.
    const auto truth = op.truth_at(cfg.crossing_time_s);
    const Eigen::Vector2d dir(std::cos(truth.heading_rad), std::sin(truth.heading_rad));
    const Eigen::Vector2d inward(-dir.y(), dir.x());
    const Eigen::Vector2d c = truth.position_m + 2.0 * dir;
    const double approach_m = 7.0, v = 1.2;
    WalkerConfig w;
    w.id = next_id++;
    w.path_m = {c + approach_m * inward, c - 0.6 * cfg.edge_inset_m * inward,
                c - 0.6 * cfg.edge_inset_m * inward + 10.0 * dir};
    w.speed = {{0.0, v}};
    w.start_offset_m = approach_m - v * cfg.crossing_time_s;
    w.height_m = 1.68;
    scene.add_walker(Walker(w));
  }
  for (int k = 0; k < cfg.extra_walkers; ++k) {
    WalkerConfig w;
    w.id = next_id++;
    for (int i = 0; i < 4; ++i)
      w.path_m.emplace_back(-4.0 + (cfg.length_m + 8.0) * uni(rng),
                            -1.0 + (cfg.width_m + 4.0) * uni(rng));
    w.closed = true;
    w.speed = {{0.0, 0.5 + uni(rng)}};
    w.height_m = 1.55 + 0.35 * uni(rng);
    scene.add_walker(Walker(w));
  }
  return scene;
}

}  // namespace fieldlidar::sim
