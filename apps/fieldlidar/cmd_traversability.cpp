// fieldlidar traversability INPUT --out DIR: the traversability map of one scan or survey file
// (seed 004, steps b-d) as a nav2 map_server map, a top-down picture and a summary.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <string>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/cloud_file.hpp"
#include "fieldlidar/io/file_util.hpp"
#include "fieldlidar/io/nav2_map.hpp"
#include "fieldlidar/segmentation/ground.hpp"
#include "fieldlidar/terrain/traversability.hpp"
#include "support/canvas.hpp"
#include "support/option_checks.hpp"
#include "support/sensor_choice.hpp"
#include "support/warnings.hpp"

namespace fieldlidar::app {
namespace {

namespace fs = std::filesystem;

struct TraversabilityOptions {
  std::string input, out, sensor, mode = "trinary";
  double cell_m = 0;  ///< 0: 0.5 m for a sweep, from the point density for a survey
  bool force = false;
};

// tau 0 red, 1 green; impassable black, unknown grey.
Rgb cell_colour(float tau, bool impassable) {
  if (!std::isfinite(tau)) return {0.6, 0.6, 0.6};
  if (impassable) return {0, 0, 0};
  const double t = std::clamp(double(tau), 0.0, 1.0);
  return {std::min(1.0, 2.0 * (1.0 - t)), std::min(1.0, 2.0 * t), 0.1};
}

void draw(const Grid2D& map, const std::string& title, const fs::path& path, bool force) {
  const GridGeometry& g = map.geometry();
  const Eigen::Vector2d size(g.width * g.resolution_m, g.height * g.resolution_m);
  TopDownCanvas canvas(g.origin_m, g.origin_m + size, 1000);
  const auto tau = map.layer(terrain::layer::kTraversability);
  const auto impassable = map.layer(terrain::layer::kImpassable);
  for (int iy = 0; iy < g.height; ++iy)
    for (int ix = 0; ix < g.width; ++ix) {
      const std::size_t i = g.linear_index(ix, iy);
      canvas.cell(g, ix, iy, cell_colour(tau[i], impassable[i] > 0.5f));
    }
  canvas.title(title);
  canvas.legend({{"best (tau 1)", cell_colour(1.0f, false)},
                 {"poor (tau 0.5)", cell_colour(0.5f, false)},
                 {"worst passable (tau 0)", cell_colour(0.0f, false)},
                 {"impassable", cell_colour(0.0f, true)},
                 {"unknown", cell_colour(NAN, false)}});
  canvas.save_png(path, force);
}

// A survey's cell holds about 8 returns on average (an airborne tile of ~1 point/m2 gets ~3 m
// cells, where 0.5 m cells would be nearly all unknown), never below `least_m`, in 0.5 m steps.
double survey_cell_m(const PointCloud& cloud, double least_m) {
  const Bounds3 b = compute_bounds(cloud);
  if (b.empty()) return least_m;
  const Eigen::Vector3d size = b.max - b.min;
  const double area_m2 = std::max(1e-6, size.x() * size.y());
  const double density = double(cloud.valid_count()) / area_m2;
  const double cell = std::ceil(std::sqrt(8.0 / density) / 0.5) * 0.5;
  return std::clamp(cell, least_m, 10.0);
}

// The map's tau layer on the same cells, placed in the input's own coordinates (origin_m added).
Grid2D placed_tau(const Grid2D& map, const Eigen::Vector3d& origin_m) {
  GridGeometry g = map.geometry();
  g.origin_m += origin_m.head<2>();
  Grid2D out(g);
  const auto tau = map.layer(terrain::layer::kTraversability);
  std::copy(tau.begin(), tau.end(), out.add_layer("tau", 0.0f).begin());
  return out;
}

void run(const TraversabilityOptions& o) {
  const fs::path out(o.out);
  const std::vector<std::string> names = {"traversability.yaml", "traversability.pgm",
                                          "traversability.png", "summary.json"};
  if (fs::exists(out) && !fs::is_directory(out))
    throw Error("traversability: --out " + o.out + " is not a folder");
  fs::create_directories(out);
  for (const auto& n : names) io::check_writable(out / n, o.force, {fs::path(o.input)});
  const PointCloud cloud = io::read_cloud(o.input);
  if (cloud.valid_count() == 0)
    throw Error(o.input + ": no valid point (" + std::to_string(cloud.size()) +
                " points): nothing to map");

  const auto t0 = std::chrono::steady_clock::now();
  const segmentation::SweepCheck check = segmentation::check_sweep(cloud);
  const bool sweep = check.sweep || !o.sensor.empty();
  terrain::TraversabilityConfig cfg;
  Grid2D map;
  std::string sensor_name;
  cfg.cell_m = o.cell_m > 0 ? o.cell_m : sweep ? cfg.cell_m : survey_cell_m(cloud, cfg.cell_m);
  if (sweep) {
    const SensorModel sensor = sensor_for(cloud, o.input, o.sensor);
    sensor_name = sensor.name;
    map = terrain::map_scan(cloud, sensor, Pose::Identity(), cfg);
  } else {
    warn(
        fmt::format("{}: not one sensor sweep ({}); mapped as a survey of the whole area (give "
                    "--sensor for a sweep)",
                    o.input, check.reason));
    map = terrain::map_area(cloud, cfg);
  }
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();

  io::Nav2MapConfig nav;
  nav.mode = o.mode;
  const io::Nav2Map nav2 =
      io::encode_nav2_map(placed_tau(map, cloud.origin_m), "tau", "traversability.pgm", nav);
  io::write_file_atomic(out / "traversability.pgm", nav2.pgm, o.force);
  io::write_file_atomic(out / "traversability.yaml", nav2.yaml, o.force);
  draw(map,
       fmt::format("{}: traversability, {} m cells", fs::path(o.input).filename().string(),
                   map.geometry().resolution_m),
       out / "traversability.png", o.force);

  const GridGeometry& g = map.geometry();
  const auto tau = map.layer(terrain::layer::kTraversability);
  const auto impassable = map.layer(terrain::layer::kImpassable);
  std::size_t known = 0, blocked = 0;
  for (std::size_t i = 0; i < tau.size(); ++i) {
    if (!std::isfinite(tau[i])) continue;
    ++known;
    if (impassable[i] > 0.5f || tau[i] <= 0.0f) ++blocked;
  }
  nlohmann::json j;
  j["file"] = o.input;
  j["input"] = sweep ? "sweep" : "survey";
  j["sensor"] = sweep ? nlohmann::json(sensor_name) : nlohmann::json(nullptr);
  j["points"] = cloud.size();
  j["resolution_m"] = g.resolution_m;
  j["width_cells"] = g.width;
  j["height_cells"] = g.height;
  j["origin_m"] = {g.origin_m.x() + cloud.origin_m.x(), g.origin_m.y() + cloud.origin_m.y()};
  j["cells"] = g.cell_count();
  j["cells_known"] = known;
  j["cells_passable"] = known - blocked;
  j["cells_impassable"] = blocked;
  j["coverage"] = g.cell_count() ? double(known) / double(g.cell_count()) : 0.0;
  j["time_ms"] = ms;
  io::write_file_atomic(out / "summary.json", j.dump(1) + "\n", o.force);
  fmt::print(
      "{}: {} points ({}), {} x {} cells of {} m: {} known ({:.1f} %), {} passable, {} "
      "impassable, {:.0f} ms -> {}\n",
      o.input, cloud.size(), sweep ? "sweep, " + sensor_name : std::string("survey"), g.width,
      g.height, g.resolution_m, known, 100.0 * j["coverage"].get<double>(), known - blocked,
      blocked, ms, out.string());
}

}  // namespace

void add_traversability_command(CLI::App& app) {
  auto o = std::make_shared<TraversabilityOptions>();
  auto* cmd = app.add_subcommand(
      "traversability",
      "Where a ground robot can drive: traversability map of one scan or survey file (nav2 "
      "map, PNG, summary)");
  cmd->add_option("INPUT", o->input, "Scan or survey file (.pcd, .las, .ply, .bin)")->required();
  cmd->add_option("--out", o->out, "Output folder (traversability.yaml/.pgm/.png, summary.json)")
      ->required();
  cmd->add_option("--sensor", o->sensor,
                  "Sensor preset: map INPUT as one sweep of it (default: a sweep's from its "
                  "rings; a cloud that is not one sweep is mapped as a survey)");
  cmd->add_option("--mode", o->mode,
                  "nav2 map mode: trinary (occupied/free/unknown) or scale (cost kept)")
      ->capture_default_str()
      ->check(CLI::IsMember({"trinary", "scale"}));
  cmd->add_option("--cell", o->cell_m,
                  "Map cell side (m); default 0.5 for a sweep, from the point density for a "
                  "survey")
      ->check(real_in(0.1, 10.0));
  cmd->add_flag("-f,--force", o->force, "Replace existing output files");
  cmd->callback([o] { run(*o); });
}

}  // namespace fieldlidar::app
