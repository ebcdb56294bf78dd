// fieldlidar traversability INPUT [--poses POSES] [--robot config.yaml] --out DIR: the
// traversability map (seed 004, steps b-d) of one scan, a survey file, or a sequence of scans fused
// over time (placed by --poses, else by the lidar odometry), as a nav2 map_server map, one GeoTIFF
// per layer, a top-down picture and a summary.

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/cloud_file.hpp"
#include "fieldlidar/io/file_util.hpp"
#include "fieldlidar/io/geotiff.hpp"
#include "fieldlidar/io/nav2_map.hpp"
#include "fieldlidar/segmentation/ground.hpp"
#include "fieldlidar/terrain/robot_config.hpp"
#include "fieldlidar/terrain/terrain_map.hpp"
#include "fieldlidar/terrain/traversability.hpp"
#include "support/option_checks.hpp"
#include "support/output_folder.hpp"
#include "support/sensor_choice.hpp"
#include "support/sweep_levelling.hpp"
#include "support/terrain_picture.hpp"
#include "support/traversability_sequence.hpp"
#include "support/warnings.hpp"

namespace fieldlidar::app {
namespace {

namespace fs = std::filesystem;

struct TraversabilityOptions {
  std::string input, out, sensor, mode = "trinary", poses, robot;
  double cell_m = 0;       ///< 0: 0.5 m for a sweep, from the point density for a survey
  double min_range_m = 0;  ///< returns nearer the sensor are dropped (the robot's body); 0: none
  bool force = false;
};

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

/// A map without one known cell is written (it is what the input gives) but said: the usual
/// causes, and the options that change them.
void warn_nothing_known(const TraversabilityOptions& o, const GridGeometry& g) {
  std::string change;
  if (o.min_range_m > 0) change += fmt::format(", a smaller --min-range than {} m", o.min_range_m);
  if (!o.sensor.empty()) change += ", no --sensor if the input is a survey, not one sweep of it";
  warn(
      fmt::format("{}: no cell of the {} x {} map is known: too few returns on the ground of "
                  "each {} m cell to judge it; try a larger --cell{}",
                  o.input, g.width, g.height, g.resolution_m, change));
}

void write_geotiffs(const Grid2D& map, const Eigen::Vector3d& origin_m, const fs::path& dir,
                    bool force) {
  fs::create_directories(dir);
  io::GeoTiffConfig gt;
  gt.origin_offset_m = origin_m.head<2>();
  for (const std::string& name : map.layer_names())
    io::write_file_atomic(dir / (name + ".tif"), io::encode_geotiff(map, name, gt), force);
}

void run(const TraversabilityOptions& o) {
  const fs::path out(o.out);
  const std::vector<std::string> names = {"traversability.yaml", "traversability.pgm",
                                          "traversability.png", "summary.json"};
  if (fs::exists(out) && !fs::is_directory(out))
    throw Error("traversability: --out " + o.out + " is not a folder");
  terrain::TraversabilityConfig cfg;
  if (!o.robot.empty()) cfg.robot = terrain::load_robot_config(o.robot);
  const OutputFolder folder(out);  // gone again if the input is refused before any output
  for (const auto& n : names) io::check_writable(out / n, o.force, {fs::path(o.input)});

  // A sequence: a folder, a glob, a capture, or any input with --poses.
  const fs::path in(o.input);
  const std::string ext = in.extension().string();
  const bool sequence = !o.poses.empty() || fs::is_directory(in) ||
                        o.input.find('*') != std::string::npos || ext == ".pcap" || ext == ".bag";
  Grid2D map;
  PointCloud cloud;
  nlohmann::json j;
  j["file"] = o.input;
  const auto t0 = std::chrono::steady_clock::now();
  std::string what;
  if (sequence) {
    if (o.cell_m > 0) cfg.cell_m = o.cell_m;
    SequenceResult r = map_sequence({o.input, o.poses, o.sensor, o.min_range_m}, cfg);
    map = std::move(r.map);
    j["input"] = "sequence";
    j["sensor"] = r.sensor;
    j["frames"] = r.frames;
    j["frames_without_pose"] = r.skipped;
    j["frames_deskewed"] = r.deskewed;
    j["placed_by"] = r.placed_by;
    j["path_length_m"] = r.path.path_length_m();
    j["map_update_ms_per_frame"] = r.update_ms / double(r.frames);
    what = fmt::format("{} frames fused, {}", r.frames, r.sensor);
  } else {
    cloud = io::read_cloud(o.input);
    if (cloud.valid_count() == 0)
      throw Error(o.input + ": no valid point (" + std::to_string(cloud.size()) +
                  " points): nothing to map");
    if (const auto why = segmentation::implausible_span(cloud)) throw Error(o.input + ": " + *why);
    const segmentation::SweepCheck check = segmentation::check_sweep(cloud);
    const bool sweep = check.sweep || !o.sensor.empty();
    if (!sweep && o.min_range_m > 0.0)
      throw Error(
          fmt::format("--min-range: {} is not one sensor sweep ({}), so it has no sensor "
                      "to measure ranges from (give --sensor for a sweep)",
                      o.input, check.reason));
    drop_nearer_than(cloud, o.min_range_m);
    if (cloud.valid_count() == 0)
      throw Error(fmt::format("{}: no valid point beyond --min-range {} m: nothing to map", o.input,
                              o.min_range_m));
    cfg.cell_m = o.cell_m > 0 ? o.cell_m : sweep ? cfg.cell_m : survey_cell_m(cloud, cfg.cell_m);
    if (sweep) {
      const SensorModel sensor = sensor_for(cloud, o.input, o.sensor);
      j["sensor"] = sensor.name;
      map = terrain::map_scan(cloud, sensor,
                              levelling_pose(cloud, cfg.ground.levelling, o.input, &j), cfg);
      what = "sweep, " + sensor.name;
    } else {
      warn(
          fmt::format("{}: not one sensor sweep ({}); mapped as a survey of the whole area (give "
                      "--sensor for a sweep)",
                      o.input, check.reason));
      // A LAS file's classes say where the water is (class 9).
      std::vector<std::uint8_t> water;
      std::string lower = ext;
      std::transform(lower.begin(), lower.end(), lower.begin(),
                     [](unsigned char ch) { return char(std::tolower(ch)); });
      if ((lower == ".las" || lower == ".laz") && cloud.has_labels()) {
        water.resize(cloud.size());
        for (std::size_t i = 0; i < cloud.size(); ++i) water[i] = cloud.labels[i] == 9;
        j["water_points"] = std::count(water.begin(), water.end(), std::uint8_t(1));
      }
      terrain::FusionConfig fusion;
      fusion.layers = cfg;
      map = terrain::map_area_fused(cloud, fusion, water);
      what = "survey";
    }
    j["input"] = sweep ? "sweep" : "survey";
    j["points"] = cloud.size();
  }
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();

  io::Nav2MapConfig nav;
  nav.mode = o.mode;
  const io::Nav2Map nav2 =
      io::encode_nav2_map(placed_tau(map, cloud.origin_m), "tau", "traversability.pgm", nav);
  io::write_file_atomic(out / "traversability.pgm", nav2.pgm, o.force);
  io::write_file_atomic(out / "traversability.yaml", nav2.yaml, o.force);
  write_geotiffs(map, cloud.origin_m, out / "layers", o.force);
  draw_terrain_map(
      map, cfg.robot,
      fmt::format("{}: traversability, {} m cells ({})", fs::path(o.input).filename().string(),
                  map.geometry().resolution_m, what),
      out / "traversability.png", o.force);

  const GridGeometry& g = map.geometry();
  const auto tau = map.layer(terrain::layer::kTraversability);
  const auto impassable = map.layer(terrain::layer::kImpassable);
  std::size_t known = 0, blocked = 0;
  for (std::size_t i = 0; i < tau.size(); ++i) {
    if (!std::isfinite(impassable[i])) continue;
    ++known;
    if (impassable[i] > 0.5f || !(tau[i] > 0.0f)) ++blocked;
  }
  if (known == 0) warn_nothing_known(o, g);
  j["min_range_m"] = o.min_range_m;
  j["robot"] = {{"length_m", cfg.robot.length_m},
                {"width_m", cfg.robot.width_m},
                {"max_slope_deg", cfg.robot.max_slope_deg},
                {"max_step_m", cfg.robot.max_step_m},
                {"clearance_m", cfg.robot.clearance_m},
                {"min_obstacle_height_m", cfg.robot.min_obstacle_height_m},
                {"min_turn_radius_m", cfg.robot.min_turn_radius_m}};
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
      "{}: {}: {} x {} cells of {} m: {} known ({:.1f} %), {} passable, {} impassable, {:.0f} ms "
      "-> {}\n",
      o.input, what, g.width, g.height, g.resolution_m, known, 100.0 * j["coverage"].get<double>(),
      known - blocked, blocked, ms, out.string());
}
}  // namespace

void add_traversability_command(CLI::App& app) {
  auto o = std::make_shared<TraversabilityOptions>();
  auto* cmd = app.add_subcommand(
      "traversability",
      "Where a ground robot can drive: traversability map of one scan, a survey file or a "
      "sequence fused over time (nav2 map, GeoTIFF layers, PNG, summary)");
  cmd->add_option("INPUT", o->input,
                  "Scan or survey file (.pcd, .las, .ply, .bin), or a sequence (folder, glob, "
                  "pcap, bag, simulator folder) fused over time")
      ->required();
  cmd->add_option("--poses", o->poses,
                  "Poses of the sequence's frames (KITTI: one per frame, e.g. a simulator "
                  "folder's poses.txt; or TUM, by stamp); default: the lidar odometry")
      ->check(CLI::ExistingFile);
  cmd->add_option("--robot", o->robot,
                  "Robot config YAML (length_m, width_m, max_slope_deg, max_step_m, clearance_m, "
                  "min_obstacle_height_m, min_turn_radius_m; see config/robot_seed004.yaml); "
                  "default: the seed's 0.93 x 0.58 m robot")
      ->check(CLI::ExistingFile);
  cmd->add_option("--out", o->out,
                  "Output folder (traversability.yaml/.pgm/.png, layers/*.tif, summary.json)")
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
  cmd->add_option("--min-range", o->min_range_m,
                  "Returns nearer than this to the sensor are dropped before mapping (m, 3D "
                  "range): the robot's own body, which would block the cells it stands on "
                  "(RELLIS-3D's vehicle: 2.3 m); a sweep or a sequence only; 0: keep all")
      ->capture_default_str()
      ->check(real_in(0.0, 50.0));
  cmd->add_flag("-f,--force", o->force, "Replace existing output files");
  cmd->callback([o] { run(*o); });
}

}  // namespace fieldlidar::app
