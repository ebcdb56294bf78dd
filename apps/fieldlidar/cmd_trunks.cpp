// fieldlidar trunks INPUT --out DIR: tree trunks of one scan or plot file (seed 003, steps 1-3):
// trees.csv, trees.geojson and a top-down picture of the stems as DBH circles over the points.

#include <filesystem>
#include <memory>
#include <string>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "fieldlidar/core/error.hpp"
#include "fieldlidar/forest/trunks.hpp"
#include "fieldlidar/io/cloud_file.hpp"
#include "fieldlidar/io/file_util.hpp"
#include "fieldlidar/segmentation/ground.hpp"
#include "support/canvas.hpp"
#include "support/option_checks.hpp"
#include "support/sensor_choice.hpp"

namespace fieldlidar::app {
namespace {

namespace fs = std::filesystem;

struct TrunksOptions {
  std::string input, out, sensor;
  double max_radius_m = 0.6;
  double slice_m = 0.15;
  bool force = false;
};

std::string trees_csv(const std::vector<forest::Tree>& trees, const Eigen::Vector3d& origin) {
  std::string s =
      "id,x_m,y_m,z_base_m,dbh_m,axis_x,axis_y,axis_z,height_seen_m,arc_deg,"
      "residual_m,observations\n";
  for (const auto& t : trees) {
    const Eigen::Vector3d b = t.base_m + origin;
    s +=
        fmt::format("{},{:.3f},{:.3f},{:.3f},{:.4f},{:.4f},{:.4f},{:.4f},{:.2f},{:.1f},{:.4f},{}\n",
                    t.id, b.x(), b.y(), b.z(), t.dbh_m, t.axis.x(), t.axis.y(), t.axis.z(),
                    t.z_max_seen_m - t.z_min_seen_m, t.arc_deg, t.residual_m, t.observations);
  }
  return s;
}

std::string trees_geojson(const std::vector<forest::Tree>& trees, const Eigen::Vector3d& origin) {
  nlohmann::json fc = {{"type", "FeatureCollection"}, {"features", nlohmann::json::array()}};
  for (const auto& t : trees) {
    const Eigen::Vector3d b = t.base_m + origin;
    fc["features"].push_back(
        {{"type", "Feature"},
         {"geometry", {{"type", "Point"}, {"coordinates", {b.x(), b.y(), b.z()}}}},
         {"properties",
          {{"id", t.id},
           {"dbh_m", t.dbh_m},
           {"height_seen_m", t.z_max_seen_m - t.z_min_seen_m},
           {"arc_deg", t.arc_deg},
           {"residual_m", t.residual_m},
           {"observations", t.observations},
           {"ground_found", t.ground_found}}}});
  }
  return fc.dump(1) + "\n";
}

void draw(const PointCloud& cloud, const std::vector<std::uint8_t>& ground,
          const std::vector<forest::Tree>& trees, const fs::path& path, bool force) {
  const Bounds3 b = compute_bounds(cloud);
  if (b.empty()) return;
  TopDownCanvas canvas(b.min.head<2>(), b.max.head<2>());
  const std::size_t step = std::max<std::size_t>(1, cloud.size() / 200000);
  for (std::size_t i = 0; i < cloud.size(); i += step)
    if (cloud.points[i].is_valid())
      canvas.dot({cloud.points[i].x, cloud.points[i].y},
                 ground[i] ? Rgb{0.8, 0.75, 0.6} : Rgb{0.6, 0.65, 0.7}, 0.6);
  for (const auto& t : trees) {
    const Eigen::Vector2d c = t.at_height(1.3).head<2>();
    canvas.circle(c, t.dbh_m / 2, palette(t.id), 2.0);
    canvas.text(c + Eigen::Vector2d(t.dbh_m / 2 + 0.1, 0), std::to_string(t.id), {0, 0, 0}, 11);
  }
  canvas.title(fmt::format("trunks: {} trees", trees.size()));
  canvas.legend({{"ground", {0.8, 0.75, 0.6}},
                 {"other points", {0.6, 0.65, 0.7}},
                 {"stem at 1.3 m (DBH)", palette(1)}});
  canvas.save_png(path, force);
}

void run(const TrunksOptions& o) {
  const fs::path out(o.out);
  const std::vector<std::string> names = {"trees.csv", "trees.geojson", "trees.png"};
  fs::create_directories(out);
  for (const auto& n : names) io::check_writable(out / n, o.force, {fs::path(o.input)});
  const PointCloud cloud = io::read_cloud(o.input);
  // A sweep (rings, or points around the sensor) gets the robust ground; a plot file the grid.
  segmentation::GroundResult ground;
  const bool sweep = segmentation::check_sweep(cloud).sweep;
  if (sweep) {
    ground = segmentation::segment_ground(cloud, sensor_for(cloud, o.input, o.sensor));
  } else {
    ground = segmentation::ground_grid(cloud);
  }
  forest::TreeConfig cfg;
  cfg.max_radius_m = o.max_radius_m;
  cfg.segments.max_radius_m = o.max_radius_m;
  cfg.segments.slice_m = o.slice_m;
  const auto result = forest::extract_trees(cloud, ground.is_ground, cfg);
  io::write_file_atomic(out / "trees.csv", trees_csv(result.trees, cloud.origin_m), o.force);
  io::write_file_atomic(out / "trees.geojson", trees_geojson(result.trees, cloud.origin_m),
                        o.force);
  draw(cloud, ground.is_ground, result.trees, out / "trees.png", o.force);
  fmt::print("{}: {} points ({}), {} ground; {} scan segments, {} stacks, {} trees -> {}\n",
             o.input, cloud.size(),
             fmt::format("{}, {}", sweep ? "sweep" : "plot",
                         cloud.fields.ring ? "rings" : "horizontal slices"),
             ground.ground_count, result.segments, result.stacks, result.trees.size(),
             out.string());
}

}  // namespace

void add_trunks_command(CLI::App& app) {
  auto o = std::make_shared<TrunksOptions>();
  auto* cmd = app.add_subcommand(
      "trunks", "Tree trunks of one scan or plot file: positions, DBH at 1.3 m, quality");
  cmd->add_option("INPUT", o->input, "Scan or plot file (.pcd, .las, .ply, .bin)")->required();
  cmd->add_option("--out", o->out, "Output folder (trees.csv, trees.geojson, trees.png)")
      ->required();
  cmd->add_option("--sensor", o->sensor, "Sensor preset for a sweep; default from the rings");
  cmd->add_option("--max-radius", o->max_radius_m, "Largest stem radius U (m)")
      ->check(real_in(0.05, 3.0))
      ->capture_default_str();
  cmd->add_option("--slice", o->slice_m, "Slice thickness for clouds without rings (m)")
      ->check(real_in(0.02, 1.0))
      ->capture_default_str();
  cmd->add_flag("-f,--force", o->force, "Replace existing output files");
  cmd->callback([o] { run(*o); });
}

}  // namespace fieldlidar::app
