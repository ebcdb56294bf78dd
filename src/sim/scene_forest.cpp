// The forest scene of seed 003: trunks of known base, axis and DBH on an uneven floor.

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>

#include "fieldlidar/sim/scenes.hpp"

namespace fieldlidar::sim {

namespace {

double distance_to_polyline(const Eigen::Vector2d& p, const std::vector<Eigen::Vector2d>& line) {
  double best = 1e300;
  for (std::size_t i = 0; i + 1 < line.size(); ++i) {
    const Eigen::Vector2d ab = line[i + 1] - line[i];
    const double u = std::clamp((p - line[i]).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
    best = std::min(best, (p - (line[i] + u * ab)).norm());
  }
  return best;
}

Eigen::Vector3d tilted_axis(double tilt_rad, double azimuth_rad) {
  return {std::sin(tilt_rad) * std::cos(azimuth_rad), std::sin(tilt_rad) * std::sin(azimuth_rad),
          std::cos(tilt_rad)};
}

}  // namespace

Scene make_forest_scene(const ForestConfig& cfg, std::uint64_t seed) {
  if (!(cfg.trees_per_ha >= 0 && cfg.trees_per_ha <= 2000) || !(cfg.dbh_min_m > 0) ||
      !(cfg.dbh_max_m >= cfg.dbh_min_m))
    throw std::invalid_argument(
        "ForestConfig: trees_per_ha in [0, 2000], 0 < dbh_min_m <= dbh_max_m");
  std::mt19937_64 rng(seed * 15485863 + 3);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  const double sx = cfg.size_x_m, sy = cfg.size_y_m;
  const double p1 = 2 * std::numbers::pi * uni(rng), p2 = 2 * std::numbers::pi * uni(rng),
               p3 = 2 * std::numbers::pi * uni(rng);
  const double relief = cfg.floor_relief_m;
  // Long slope, rolling undulation and a rough micro-relief (roots, litter) of a few cm.
  const auto height = [&](double x, double y) {
    return 0.02 * x +
           relief * (0.6 * std::sin(0.11 * x + p1) * std::cos(0.09 * y + p2) +
                     0.3 * std::sin(0.23 * x - 0.17 * y + p3)) +
           0.03 * std::sin(2.1 * x + p2) * std::sin(1.7 * y + p1);
  };
  Scene scene(SceneKind::kForest, HeightField({0.0, 0.0}, {sx, sy}, 0.25, height), seed);
  scene.set_sensor_height_m(0.9);
  scene.set_robot_speed_m_s(0.8);
  const auto vegetation = make_label(LabelClass::kVegetation);

  // The robot's winding route through the stand; trunks keep clear of it.
  std::vector<Eigen::Vector2d> route;
  for (double x = 4.0; x <= sx - 4.0 + 1e-9; x += 2.0)
    route.emplace_back(x, 0.5 * sy + 0.12 * sy * std::sin(2 * std::numbers::pi * x / sx * 1.5));
  scene.set_robot_route(route, false);

  const int n_trees = static_cast<int>(std::round(cfg.trees_per_ha * sx * sy / 10000.0));
  std::vector<std::pair<Eigen::Vector2d, double>> placed;  // position, radius at the base
  std::uint16_t id = 1;
  for (int attempt = 0; attempt < n_trees * 50 && int(placed.size()) < n_trees; ++attempt) {
    const Eigen::Vector2d p(1.5 + (sx - 3.0) * uni(rng), 1.5 + (sy - 3.0) * uni(rng));
    // Small trees are the majority: dbh skewed to the lower end of the range.
    const double u = uni(rng);
    const double dbh = cfg.dbh_min_m + (cfg.dbh_max_m - cfg.dbh_min_m) * u * u;
    if (distance_to_polyline(p, route) < cfg.corridor_half_width_m + dbh) continue;
    bool clear = true;
    for (const auto& [q, r] : placed)
      if ((p - q).norm() < 1.2 + r + dbh / 2) clear = false;
    if (!clear) continue;
    placed.emplace_back(p, dbh / 2);

    TreeTruth t;
    t.id = id++;
    t.dbh_m = dbh;
    t.base_m = {p.x(), p.y(), scene.ground_height_at(p)};
    t.leaning = uni(rng) < cfg.leaning_fraction;
    const double tilt = t.leaning ? (6.0 + 9.0 * uni(rng)) * std::numbers::pi / 180
                                  : 1.5 * uni(rng) * std::numbers::pi / 180;
    t.axis = tilted_axis(tilt, 2 * std::numbers::pi * uni(rng));
    t.height_m = 10.0 + 12.0 * uni(rng) + 10.0 * dbh;
    t.forked = uni(rng) < cfg.forked_fraction;
    const auto trunk_label = make_label(LabelClass::kTrunk, t.id);
    // Linear taper (at most 4 mm of radius per metre, the top keeping 30 % of the radius), exact
    // DBH/2 at 1.3 m along the axis.
    const double trunk_len = t.forked ? 3.0 + 4.0 * uni(rng) : t.height_m;
    t.taper_m_per_m = std::min(0.004, 0.35 * dbh / (t.height_m - 1.3));
    const auto radius_at = [&](double l) { return t.radius_at(l); };
    const Eigen::Vector3d below = t.base_m - 0.4 * t.axis;  // sunk into the floor
    const Eigen::Vector3d top = t.base_m + trunk_len * t.axis;
    scene.add_mesh(
        make_cylinder(below, top, radius_at(-0.4), radius_at(trunk_len), 32, trunk_label));
    std::vector<Eigen::Vector3d> crowns;
    if (t.forked) {
      t.fork_height_m = trunk_len;
      const double az = 2 * std::numbers::pi * uni(rng);
      for (int side : {-1, 1}) {
        const Eigen::Vector3d stem_axis =
            (t.axis + 0.35 * side * Eigen::Vector3d(std::cos(az), std::sin(az), 0)).normalized();
        const double len = t.height_m - trunk_len;
        const double r0 = 0.75 * radius_at(trunk_len);
        scene.add_mesh(make_cylinder(top - 0.1 * t.axis, top + len * stem_axis, r0,
                                     std::max(0.03, r0 - 0.004 * len), 20, trunk_label));
        crowns.push_back(top + len * stem_axis);
      }
    } else {
      crowns.push_back(top);
    }
    // Low branches between 1.5 and 3 m.
    const int low = uni(rng) < cfg.low_branch_fraction ? 1 + int(3 * uni(rng)) : 0;
    t.low_branches = low;
    for (int b = 0; b < low; ++b) {
      const double at = 1.5 + 1.5 * uni(rng);
      const double az = 2 * std::numbers::pi * uni(rng),
                   up = (10 + 30 * uni(rng)) * std::numbers::pi / 180;
      const Eigen::Vector3d dir(std::cos(az) * std::cos(up), std::sin(az) * std::cos(up),
                                std::sin(up));
      const Eigen::Vector3d start = t.base_m + at * t.axis;
      scene.add_mesh(make_cylinder(start, start + (1.0 + 1.5 * uni(rng)) * dir,
                                   0.03 + 0.04 * uni(rng), 0.015, 8, vegetation, false));
    }
    for (const auto& c : crowns) {
      const double cr = 1.5 + 2.0 * uni(rng) + 2.0 * dbh;
      scene.add_mesh(make_blob(c - Eigen::Vector3d(0, 0, 0.5 * cr), {cr, cr, 1.3 * cr}, 0.25, rng,
                               vegetation, 6, 10));
    }
    scene.add_tree(t);
  }
  // Shrubs on the floor, off the route.
  const int n_shrubs = static_cast<int>(std::round(cfg.shrubs_per_ha * sx * sy / 10000.0));
  for (int k = 0, tries = 0; k < n_shrubs && tries < n_shrubs * 20; ++tries) {
    const Eigen::Vector2d p(sx * uni(rng), sy * uni(rng));
    const double r = 0.3 + 0.5 * uni(rng);
    if (distance_to_polyline(p, route) < cfg.corridor_half_width_m + r) continue;
    bool clear = true;
    for (const auto& [q, rq] : placed)
      if ((p - q).norm() < r + rq + 0.2) clear = false;
    if (!clear) continue;
    ++k;
    const double z = scene.ground_height_at(p);
    scene.add_mesh(
        make_blob({p.x(), p.y(), z + 0.6 * r}, {r, r, 0.8 * r}, 0.3, rng, vegetation, 5, 8));
    scene.add_obstacle({p, r, 0.0, 1.4 * r, LabelClass::kVegetation});
  }
  return scene;
}

}  // namespace fieldlidar::sim
