#include "support/sim_preview.hpp"

#include <algorithm>
#include <optional>
#include <set>
#include <utility>

#include <fmt/core.h>

#include "support/canvas.hpp"

namespace fieldlidar::app {

namespace {

Rgb class_colour(LabelClass c) {
  switch (c) {
    case LabelClass::kTrunk:
      return {0.45, 0.28, 0.12};
    case LabelClass::kVegetation:
      return {0.18, 0.55, 0.2};
    case LabelClass::kStructure:
      return {0.42, 0.45, 0.55};
    case LabelClass::kObstacle:
      return {0.35, 0.3, 0.28};
    default:
      return {0.6, 0.6, 0.6};
  }
}

constexpr double kSectionHeightM = 2.5;

/// Top-down picture: ground elevation, a plan section of the objects (what lies below 2.5 m above
/// the ground) coloured by class, and the truth.
}  // namespace

void write_preview(const std::filesystem::path& path, const sim::Scene& scene,
                   const sim::LidarSimulator& simulator, const sim::RobotMotion& motion,
                   const std::vector<double>& frame_times, const Grid2D* terrain,
                   const std::string& title, bool force) {
  TopDownCanvas canvas(scene.min_m(), scene.max_m(), 1400);
  const double cell = std::max(0.05, 1.5 / canvas.pixels_per_metre());
  const auto geom = GridGeometry::covering(scene.min_m(), scene.max_m(), cell);
  Grid2D ground(geom);
  auto elev = ground.add_layer("elevation", 0.f);
  float lo = 1e9f, hi = -1e9f;
  for (int iy = 0; iy < geom.height; ++iy)
    for (int ix = 0; ix < geom.width; ++ix) {
      const float z = float(scene.ground_height_at(geom.cell_center(ix, iy)));
      elev[geom.linear_index(ix, iy)] = z;
      lo = std::min(lo, z);
      hi = std::max(hi, z);
    }
  canvas.raster(geom, elev, lo, std::max(hi, lo + 0.1f), 0.35);
  std::set<LabelClass> drawn;
  for (int iy = 0; iy < geom.height; ++iy)
    for (int ix = 0; ix < geom.width; ++ix) {
      const auto c = geom.cell_center(ix, iy);
      // A plan section at kSectionHeightM above the ground: walk down from above; a solid entered
      // above the cut (front face) and not left before it (no back face above the cut) is cut by
      // the section.
      const double cut_z = scene.ground_height_at(c) + kSectionHeightM;
      Eigen::Vector3d o(c.x(), c.y(), cut_z + 100.0);
      std::optional<std::uint32_t> shown, inside;
      for (int k = 0; k < 16 && !shown; ++k) {
        const auto hit = simulator.cast(o, -Eigen::Vector3d::UnitZ(), 500.0);
        if (!hit) break;
        const double z = o.z() - hit->range_m;
        const bool front = hit->normal.z() > 0;
        if (z <= cut_z) {
          shown =
              inside ? *inside : hit->label;  // inside a solid that reaches down through the cut
          break;
        }
        inside = front ? std::optional<std::uint32_t>(hit->label) : std::nullopt;
        o.z() = z - 1e-3;
      }
      if (!shown || label_class(*shown) == LabelClass::kGround) continue;
      drawn.insert(label_class(*shown));
      canvas.dot(c, class_colour(label_class(*shown)), 0.6 * cell * canvas.pixels_per_metre());
    }
  if (terrain) {
    const auto& g = terrain->geometry();
    for (int iy = 0; iy < g.height; ++iy)
      for (int ix = 0; ix < g.width; ++ix)
        if (terrain->at("passable", ix, iy) == 0.f)
          canvas.dot(g.cell_center(ix, iy), {0.85, 0.1, 0.1},
                     0.3 * g.resolution_m * canvas.pixels_per_metre());
  }
  if (scene.robot_route().size() > 1)
    canvas.polyline(scene.robot_route(), {0.95, 0.55, 0.0}, 2.5, scene.robot_route_closed());
  if (!scene.operator_path().empty())
    canvas.polyline(scene.operator_path(), {0.9, 0.2, 0.1}, 1.5, true);
  for (const auto& t : scene.trunks()) {
    canvas.circle(t.base_m.head<2>(), std::max(0.15, t.dbh_m / 2), {0.1, 0.1, 0.1}, 1.5);
    canvas.text(t.base_m.head<2>() + Eigen::Vector2d(0.4, 0.2), std::to_string(t.id),
                {0.5, 0.05, 0.05}, 9.0);
  }
  // Robot trajectory over the simulated frames and its pose at the first frame.
  std::vector<Eigen::Vector2d> track;
  const double t_end =
      frame_times.empty() ? 0.0 : frame_times.back() + simulator.sensor().sweep_period_s();
  for (double t = 0; t <= t_end + 1e-9; t += 0.05)
    track.push_back(motion.T_world_lidar(t).translation().head<2>());
  if (track.size() > 1) canvas.polyline(track, {0, 0, 0}, 4.0);
  canvas.arrow(motion.T_world_lidar(0).translation().head<2>(), yaw_of(motion.T_world_lidar(0)),
               1.5, {0, 0, 0});
  // People at every frame time: body centre and the two legs.
  std::vector<std::pair<std::string, Rgb>> legend = {
      {"robot path over the frames (sensor)", {0, 0, 0}},
      {"scripted robot route", {0.95, 0.55, 0.0}}};
  for (std::size_t f = 0; f < frame_times.size(); ++f)
    for (const auto& p : scene.people_at(frame_times[f])) {
      canvas.dot(p.legs_m[0], palette(p.id), 2.0);
      canvas.dot(p.legs_m[1], palette(p.id), 2.0);
      if (f + 1 == frame_times.size()) {
        canvas.circle(p.position_m, 0.3, palette(p.id), 2.0);
        canvas.text(p.position_m + Eigen::Vector2d(0.4, 0.4), "person " + std::to_string(p.id),
                    palette(p.id));
      }
    }
  if (!scene.walkers().empty()) legend.push_back({"people: legs per frame", palette(1)});
  if (!scene.operator_path().empty()) legend.push_back({"operator path", {0.9, 0.2, 0.1}});
  if (!scene.trunks().empty()) legend.push_back({"tree truth (DBH circle, id)", {0.1, 0.1, 0.1}});
  if (terrain) legend.push_back({"impassable (truth)", {0.85, 0.1, 0.1}});
  for (const auto& [c, name] :
       {std::pair{LabelClass::kVegetation, "vegetation"},
        std::pair{LabelClass::kStructure, "structure"}, std::pair{LabelClass::kObstacle, "rock"},
        std::pair{LabelClass::kTrunk, "trunk"}})
    if (drawn.count(c)) legend.push_back({name, class_colour(c)});
  legend.push_back({fmt::format("ground elevation {:.1f} .. {:.1f} m", lo, hi), ramp(0.5)});
  canvas.legend(legend);
  canvas.title(title);
  canvas.save_png(path, force);
}

}  // namespace fieldlidar::app
