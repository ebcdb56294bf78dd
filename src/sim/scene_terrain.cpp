// The off-road scene of seed 004: slopes up to the configured maximum, a ditch, pits, a step,
// rocks, bushes and overhanging branches, with a per-cell passability truth (Scene::terrain_truth).

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>

#include "fieldlidar/core/segment_distance.hpp"
#include "fieldlidar/sim/scenes.hpp"

namespace fieldlidar::sim {

namespace {

double smoothstep(double e0, double e1, double x) {
  const double t = std::clamp((x - e0) / (e1 - e0), 0.0, 1.0);
  return t * t * (3 - 2 * t);
}

}  // namespace

Scene make_terrain_scene(const TerrainConfig& cfg, std::uint64_t seed) {
  if (!(cfg.size_x_m >= 30 && cfg.size_y_m >= 30) || !(cfg.resolution_m > 0.02) ||
      !(cfg.max_slope_deg > 5 && cfg.max_slope_deg < 60))
    throw std::invalid_argument(
        "TerrainConfig: need sizes >= 30 m, resolution_m > 0.02, max_slope_deg in (5, 60)");
  std::mt19937_64 rng(seed * 32452843 + 4);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  const double sx = cfg.size_x_m, sy = cfg.size_y_m;
  const double p1 = 2 * std::numbers::pi * uni(rng), p2 = 2 * std::numbers::pi * uni(rng);
  const double route_y = 0.5 * sy;
  // A Gaussian hill's steepest slope is A / sigma * exp(-1/2): size it to reach the maximum slope
  // (less the rolling base's 3 deg).
  const double sigma = 5.0;
  const double amp =
      std::tan((cfg.max_slope_deg - 3.0) * std::numbers::pi / 180) * sigma / std::exp(-0.5);
  const Eigen::Vector2d hill(0.75 * sx, route_y + 2.6 * sigma);
  const Eigen::Vector2d ditch_a(0.15 * sx, route_y + 5.0), ditch_b(0.35 * sx, sy - 1.0);
  const double step_y = route_y - 7.0, step_x0 = 0.4 * sx, step_x1 = 0.7 * sx;
  struct Pit {
    Eigen::Vector2d c;
    double r, depth;
  };
  std::vector<Pit> pits;
  for (int k = 0, tries = 0; k < cfg.pits && tries < 1000; ++tries) {
    const Eigen::Vector2d c(3 + (sx - 6) * uni(rng), 3 + (sy - 6) * uni(rng));
    if (std::abs(c.y() - route_y) < 5.0) continue;
    pits.push_back({c, 0.5 + 0.6 * uni(rng), 0.4 + 0.6 * uni(rng)});
    ++k;
  }
  const auto height = [&](double x, double y) {
    const Eigen::Vector2d p(x, y);
    double h = 0.6 * std::sin(0.07 * x + p1) * std::cos(0.09 * y + p2) + 0.02 * x;
    h += amp * std::exp(-(p - hill).squaredNorm() / (2 * sigma * sigma));
    // Ditch: 0.8 m deep, 1 m half-width, cosine cross-section.
    const double dd = point_segment_distance(p, ditch_a, ditch_b);
    if (dd < 1.0) h -= 0.8 * 0.5 * (1 + std::cos(std::numbers::pi * dd));
    for (const auto& pit : pits) {
      const double d = (p - pit.c).norm();
      if (d < pit.r) h -= pit.depth * (1 - smoothstep(0.6 * pit.r, pit.r, d));
    }
    // A 0.5 m terrace step along y = step_y over x in [step_x0, step_x1].
    if (x > step_x0 && x < step_x1)
      h += 0.5 * smoothstep(step_y - 0.05, step_y + 0.05, -y + 2 * step_y);
    return h;
  };
  Scene scene(SceneKind::kTerrain, HeightField({0.0, 0.0}, {sx, sy}, cfg.resolution_m, height),
              seed);
  scene.set_sensor_height_m(1.2);
  scene.set_robot_speed_m_s(1.5);

  std::vector<Eigen::Vector2d> route;
  for (double x = 3.0; x <= sx - 3.0 + 1e-9; x += 2.0)
    route.emplace_back(x, route_y + 1.5 * std::sin(2 * std::numbers::pi * x / 25.0));
  scene.set_robot_route(route, false);
  const auto near_route = [&](const Eigen::Vector2d& p, double clearance) {
    for (std::size_t i = 0; i + 1 < route.size(); ++i)
      if (point_segment_distance(p, route[i], route[i + 1]) < clearance) return true;
    return false;
  };

  for (int k = 0, tries = 0; k < cfg.rocks && tries < 5000; ++tries) {
    const Eigen::Vector2d c(1 + (sx - 2) * uni(rng), 1 + (sy - 2) * uni(rng));
    const double r = 0.15 + 0.65 * uni(rng);
    if (near_route(c, 2.5 + r)) continue;
    ++k;
    const double z = scene.ground_height_at(c);
    const double h = (0.5 + 0.4 * uni(rng)) * r;
    scene.add_mesh(make_blob({c.x(), c.y(), z}, {r, 0.8 * r, h}, 0.2, rng,
                             make_label(LabelClass::kObstacle), 5, 8));
    scene.add_obstacle({c, r, 0.0, h, LabelClass::kObstacle});
  }
  for (int k = 0, tries = 0; k < cfg.bushes && tries < 5000; ++tries) {
    const Eigen::Vector2d c(1 + (sx - 2) * uni(rng), 1 + (sy - 2) * uni(rng));
    const double r = 0.4 + 0.8 * uni(rng);
    if (near_route(c, 2.5 + r)) continue;
    ++k;
    const double z = scene.ground_height_at(c);
    scene.add_mesh(make_blob({c.x(), c.y(), z + 0.6 * r}, {r, r, 0.8 * r}, 0.3, rng,
                             make_label(LabelClass::kVegetation), 5, 8));
    scene.add_obstacle({c, r, 0.0, 1.4 * r, LabelClass::kVegetation});
  }
  // Trees beside the route whose branches reach over it at 2-2.8 m: passable below.
  for (int k = 0; k < cfg.branches; ++k) {
    const double x = 6.0 + (sx - 12.0) * (k + 0.5) / std::max(1, cfg.branches);
    const double side = k % 2 == 0 ? 1.0 : -1.0;
    const double ry = route_y + 1.5 * std::sin(2 * std::numbers::pi * x / 25.0);
    const Eigen::Vector2d trunk(x, ry + side * 3.2);
    const double z = scene.ground_height_at(trunk);
    const auto trunk_label = make_label(LabelClass::kTrunk, static_cast<std::uint16_t>(k + 1));
    scene.add_mesh(make_cylinder({trunk.x(), trunk.y(), z - 0.3}, {trunk.x(), trunk.y(), z + 5.0},
                                 0.2, 0.15, 16, trunk_label));
    scene.add_obstacle({trunk, 0.2, 0.0, 5.0, LabelClass::kTrunk});
    const double bz = scene.ground_height_at({x, ry}) + 2.0 + 0.8 * uni(rng);
    const Eigen::Vector3d start(trunk.x(), trunk.y(), z + 2.5);
    const Eigen::Vector3d end(x + 0.5, ry - side * 2.5, bz);
    scene.add_mesh(
        make_cylinder(start, end, 0.08, 0.03, 8, make_label(LabelClass::kVegetation), false));
    scene.add_obstacle({Eigen::Vector2d(x + 0.25, ry), 1.0,
                        bz - scene.ground_height_at({x, ry}) - 0.1,
                        bz - scene.ground_height_at({x, ry}) + 0.1, LabelClass::kVegetation});
    TreeTruth t;
    t.id = static_cast<std::uint16_t>(k + 1);
    t.base_m = {trunk.x(), trunk.y(), z};
    t.dbh_m = 2 * (0.2 - 0.05 * 1.6 / 5.3);
    t.height_m = 5.0;
    t.low_branches = 1;
    scene.add_tree(t);
  }
  return scene;
}

}  // namespace fieldlidar::sim
