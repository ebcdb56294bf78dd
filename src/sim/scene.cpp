#include "fieldlidar/sim/scene.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace fieldlidar::sim {

std::string to_string(SceneKind kind) {
  switch (kind) {
    case SceneKind::kLawn:
      return "lawn";
    case SceneKind::kGreenhouse:
      return "greenhouse";
    case SceneKind::kForest:
      return "forest";
    case SceneKind::kTerrain:
      return "terrain";
    case SceneKind::kCustom:
      return "custom";
  }
  return "custom";
}

std::optional<SceneKind> scene_kind_from_string(const std::string& name) {
  if (name == "lawn") return SceneKind::kLawn;
  if (name == "greenhouse") return SceneKind::kGreenhouse;
  if (name == "forest") return SceneKind::kForest;
  if (name == "terrain") return SceneKind::kTerrain;
  return std::nullopt;
}

Scene::Scene(SceneKind kind, HeightField ground, std::uint64_t seed)
    : kind_(kind), seed_(seed), ground_(std::move(ground)) {
  mesh_ = ground_.to_mesh(make_label(LabelClass::kGround));
}

std::vector<PersonTruth> Scene::people_at(double t_s) const {
  std::vector<PersonTruth> out;
  out.reserve(walkers_.size());
  for (const auto& w : walkers_) out.push_back(w.truth_at(t_s));
  return out;
}

std::vector<PersonBody> Scene::bodies_at(double t_s) const {
  std::vector<PersonBody> out;
  out.reserve(walkers_.size());
  for (const auto& w : walkers_) {
    Eigen::Vector2d xy, dir;
    w.path_point(w.arc_length_at(t_s), xy, dir);
    out.push_back(w.body_at(t_s, ground_height_at(xy)));
  }
  return out;
}

Grid2D Scene::terrain_truth(const TerrainTruthConfig& config) const {
  const auto geom = GridGeometry::covering(min_m(), max_m(), config.resolution_m);
  Grid2D grid(geom);
  auto elevation = grid.add_layer("elevation", 0.f);
  auto slope = grid.add_layer("slope_deg", 0.f);
  auto step = grid.add_layer("step_m", 0.f);
  auto obstacle = grid.add_layer("obstacle", 0.f);
  auto passable = grid.add_layer("passable", 1.f);
  // Sample the ground on a sub-grid (4 x 4 per cell, at least the heightfield's resolution) for
  // elevation range and slope.
  const int sub = std::max(
      2, static_cast<int>(std::ceil(config.resolution_m / std::max(1e-3, ground_.resolution_m()))) +
             1);
  std::vector<float> zmin(geom.cell_count()), zmax(geom.cell_count());
  for (int iy = 0; iy < geom.height; ++iy)
    for (int ix = 0; ix < geom.width; ++ix) {
      const auto idx = geom.linear_index(ix, iy);
      const Eigen::Vector2d c0 = geom.origin_m + config.resolution_m * Eigen::Vector2d(ix, iy);
      double lo = 1e9, hi = -1e9, max_slope = 0;
      for (int a = 0; a <= sub; ++a)
        for (int b = 0; b <= sub; ++b) {
          const Eigen::Vector2d p =
              c0 + config.resolution_m * Eigen::Vector2d(double(a) / sub, double(b) / sub);
          const double z = ground_.height_at(p);
          lo = std::min(lo, z);
          hi = std::max(hi, z);
          const double nz = std::clamp(ground_.normal_at(p).z(), -1.0, 1.0);
          max_slope = std::max(max_slope, std::acos(nz) * 180.0 / std::numbers::pi);
        }
      zmin[idx] = float(lo);
      zmax[idx] = float(hi);
      elevation[idx] = float(ground_.height_at(geom.cell_center(ix, iy)));
      slope[idx] = float(max_slope);
    }
  for (int iy = 0; iy < geom.height; ++iy)
    for (int ix = 0; ix < geom.width; ++ix) {
      float lo = 1e9f, hi = -1e9f;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          if (geom.contains(ix + dx, iy + dy)) {
            lo = std::min(lo, zmin[geom.linear_index(ix + dx, iy + dy)]);
            hi = std::max(hi, zmax[geom.linear_index(ix + dx, iy + dy)]);
          }
      // A step is a height jump that slope alone does not explain: compare against what the
      // allowed slope would give over the neighbourhood (3 cells).
      const double allowed =
          3 * config.resolution_m * std::tan(config.max_slope_deg * std::numbers::pi / 180.0);
      step[geom.linear_index(ix, iy)] = std::max(0.f, float((hi - lo) - allowed));
    }
  for (const auto& o : obstacles_) {
    if (!o.blocks(config.robot_clearance_m, config.min_obstacle_height_m)) continue;
    const double r = o.radius_m;
    for (int iy = 0; iy < geom.height; ++iy)
      for (int ix = 0; ix < geom.width; ++ix) {
        const Eigen::Vector2d c = geom.cell_center(ix, iy);
        const Eigen::Vector2d d =
            (c - o.center_m).cwiseAbs() - Eigen::Vector2d::Constant(config.resolution_m / 2);
        if (d.cwiseMax(0.0).norm() < r) obstacle[geom.linear_index(ix, iy)] = 1.f;
      }
  }
  for (std::size_t i = 0; i < geom.cell_count(); ++i) {
    const bool ok =
        slope[i] <= config.max_slope_deg && step[i] <= config.max_step_m && obstacle[i] == 0.f;
    passable[i] = ok ? 1.f : 0.f;
  }
  return grid;
}

}  // namespace fieldlidar::sim
