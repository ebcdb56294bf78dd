// fieldlidar plan --map DIR --start x,y,yaw --goal x,y,yaw [--robot robot.yaml] --out DIR:
// Hybrid A* (seed 004, step f) on a saved traversability map (nav2 YAML + PGM, or the
// traversability command's GeoTIFF layers): path CSV, GeoJSON, PNG and a summary.

#include <cmath>
#include <filesystem>
#include <memory>
#include <string>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/file_util.hpp"
#include "fieldlidar/planning/hybrid_astar.hpp"
#include "fieldlidar/planning/planner_for_robot.hpp"
#include "fieldlidar/terrain/robot_config.hpp"
#include "support/canvas.hpp"
#include "support/option_checks.hpp"
#include "support/output_folder.hpp"
#include "support/plan_map.hpp"
#include "support/planar_paths.hpp"

namespace fieldlidar::app {
namespace {

namespace fs = std::filesystem;

struct PlanOptions {
  std::string map, start, goal, out, robot;
  double radius_m = 0.0;  ///< 0: the robot's min_turn_radius_m
  double budget_ms = 1000.0;
  double weight = planning::PlannerConfig{}.heuristic_weight;
  int late_expansions = planning::PlannerConfig{}.late_expansions;
  bool allow_unknown = true, no_smooth = false, force = false;
};

std::string path_geojson(const planning::Path& path, const planning::Pose2& start,
                         const planning::Pose2& goal) {
  nlohmann::json line = nlohmann::json::array();
  for (const auto& p : path) line.push_back({p.pose.x_m, p.pose.y_m});
  nlohmann::json fc = {{"type", "FeatureCollection"}, {"features", nlohmann::json::array()}};
  fc["features"].push_back({{"type", "Feature"},
                            {"properties", {{"name", "path"}, {"frame", "map"}}},
                            {"geometry", {{"type", "LineString"}, {"coordinates", line}}}});
  for (const auto& [name, p] : {std::pair{"start", start}, std::pair{"goal", goal}})
    fc["features"].push_back({{"type", "Feature"},
                              {"properties", {{"name", name}, {"yaw_rad", p.yaw_rad}}},
                              {"geometry", {{"type", "Point"}, {"coordinates", {p.x_m, p.y_m}}}}});
  return fc.dump(1) + "\n";
}

void draw(const planning::PlanningMap& map, const planning::PlanResult& r,
          const planning::Pose2& start, const planning::Pose2& goal, const std::string& title,
          const fs::path& out, bool force) {
  const GridGeometry& g = map.geometry();
  TopDownCanvas canvas(
      g.origin_m, g.origin_m + Eigen::Vector2d(g.width * g.resolution_m, g.height * g.resolution_m),
      1000);
  for (int iy = 0; iy < g.height; ++iy)
    for (int ix = 0; ix < g.width; ++ix) {
      const std::size_t i = g.linear_index(ix, iy);
      const double t = map.tau(i);
      const Rgb c = map.blocked(i)  ? Rgb{0, 0, 0}
                    : !map.known(i) ? Rgb{0.6, 0.6, 0.6}
                                    : Rgb{1.0 - 0.5 * t, 1.0 - 0.2 * t, 1.0 - 0.5 * t};
      canvas.cell(g, ix, iy, c);
    }
  auto polyline = [&](const planning::Path& p, const Rgb& c, double w) {
    std::vector<Eigen::Vector2d> pts;
    for (const auto& s : p) pts.emplace_back(s.pose.x_m, s.pose.y_m);
    canvas.polyline(pts, c, w);
  };
  polyline(r.raw_path, {0.9, 0.6, 0.1}, 1.5);
  polyline(r.path, {0.1, 0.2, 0.9}, 2.5);
  for (const auto& s : r.path)
    if (s.reverse) canvas.dot({s.pose.x_m, s.pose.y_m}, {0.9, 0.1, 0.1}, 2.0);
  canvas.arrow({start.x_m, start.y_m}, start.yaw_rad, 2.0, {0.0, 0.6, 0.0});
  canvas.arrow({goal.x_m, goal.y_m}, goal.yaw_rad, 2.0, {0.8, 0.0, 0.0});
  canvas.title(title);
  canvas.legend({{"path (shortcut, smoothed)", {0.1, 0.2, 0.9}},
                 {"search path", {0.9, 0.6, 0.1}},
                 {"driven in reverse", {0.9, 0.1, 0.1}},
                 {"impassable", {0, 0, 0}},
                 {"unknown", {0.6, 0.6, 0.6}}});
  canvas.save_png(out, force);
}

void run(const PlanOptions& o) {
  const planning::Pose2 start = parse_pose(o.start, "--start");
  const planning::Pose2 goal = parse_pose(o.goal, "--goal");
  PlanMap read = read_plan_map(o.map);
  const fs::path out(o.out);
  if (fs::exists(out) && !fs::is_directory(out))
    throw Error("plan: --out " + o.out + " is not a folder");
  const OutputFolder folder(out);  // gone again if the plan is refused before any output
  for (const char* n : {"path.csv", "path_raw.csv", "path.geojson", "plan.png", "summary.json"})
    io::check_writable(out / n, o.force, read.files);

  const terrain::RobotConfig robot =
      o.robot.empty() ? terrain::RobotConfig{} : terrain::load_robot_config(o.robot);
  const Grid2D& map = read.grid;
  planning::PlannerConfig cfg = planning::planner_config_for(robot);
  if (o.radius_m > 0) cfg.min_turn_radius_m = o.radius_m;
  cfg.time_budget_ms = o.budget_ms;
  cfg.heuristic_weight = o.weight;
  cfg.late_expansions = o.late_expansions;
  cfg.smooth = !o.no_smooth;
  cfg.map.allow_unknown = o.allow_unknown;
  planning::HybridAStar planner(map, robot, cfg);
  const planning::PlanResult r = planner.plan(start, goal);

  nlohmann::json j;
  j["map"] = read.files.front().string();
  j["map_format"] = read.format;
  j["status"] = planning::to_string(r.status);
  j["start"] = {start.x_m, start.y_m, start.yaw_rad};
  j["goal"] = {goal.x_m, goal.y_m, goal.yaw_rad};
  j["min_turn_radius_m"] = cfg.min_turn_radius_m;
  j["robot"] = {{"source", o.robot.empty() ? std::string("default (seed 004 chassis)") : o.robot},
                {"length_m", robot.length_m},
                {"width_m", robot.width_m},
                {"min_turn_radius_m", robot.min_turn_radius_m}};
  j["heuristic_weight"] = cfg.heuristic_weight;
  j["late_expansions"] = cfg.late_expansions;
  j["expansions"] = r.expansions;
  j["late_weight"] = r.late_weight;  // the search went on at late_heuristic_weight
  j["search_ms"] = r.search_ms;
  j["heuristic_ms"] = r.heuristic_ms;
  j["shortcut_ms"] = r.shortcut_ms;
  j["shortcuts"] = r.shortcuts;
  j["smooth_ms"] = r.smooth_ms;
  if (r.ok()) {
    j["cost"] = r.cost;
    j["reached_by_shot"] = r.reached_by_shot;
    j["length_m"] = planning::path_length_m(r.path);
    j["direction_changes"] = planning::direction_changes(r.path);
    j["max_curvature_per_m"] = planning::max_curvature(r.path);
    j["smoothing"] = {{"length_before_m", r.smoothing.length_before_m},
                      {"length_after_m", r.smoothing.length_after_m},
                      {"turning_before_rad", r.smoothing.turning_before_rad},
                      {"turning_after_rad", r.smoothing.turning_after_rad},
                      {"blend", r.smoothing.blend}};
    io::write_file_atomic(out / "path.csv", path_csv(r.path), o.force);
    io::write_file_atomic(out / "path_raw.csv", path_csv(r.raw_path), o.force);
    io::write_file_atomic(out / "path.geojson", path_geojson(r.path, start, goal), o.force);
  }
  draw(planner.map(), r, start, goal,
       fmt::format("{}: {} ({:.1f} m, {} expansions, {:.1f} ms)",
                   read.files.front().filename().string(), planning::to_string(r.status),
                   r.ok() ? planning::path_length_m(r.path) : 0.0, r.expansions,
                   r.search_ms + r.shortcut_ms + r.smooth_ms),
       out / "plan.png", o.force);
  io::write_file_atomic(out / "summary.json", j.dump(1) + "\n", o.force);
  if (!r.ok())
    throw Error(fmt::format("plan: {} ({} expansions, {:.1f} ms); see {}",
                            planning::to_string(r.status), r.expansions, r.search_ms,
                            (out / "summary.json").string()));
  fmt::print(
      "{}: path {:.1f} m, {} direction changes, {} expansions, {:.1f} ms search + {:.1f} "
      "ms shortcuts + {:.1f} ms smoothing -> {}\n",
      read.files.front().string(), planning::path_length_m(r.path),
      planning::direction_changes(r.path), r.expansions, r.search_ms, r.shortcut_ms, r.smooth_ms,
      out.string());
}

}  // namespace

void add_plan_command(CLI::App& app) {
  auto o = std::make_shared<PlanOptions>();
  auto* cmd = app.add_subcommand(
      "plan",
      "Hybrid A* path on a saved traversability map (nav2 YAML + PGM, or the traversability "
      "command's GeoTIFF layers): CSV, GeoJSON, PNG");
  cmd->add_option("--map", o->map,
                  "A nav2 map .yaml or a folder holding one (traversability.yaml), or the "
                  "traversability command's GeoTIFF layers: its DIR/layers folder or "
                  "traversability.tif (full-precision tau; impassable.tif and points.tif beside "
                  "it are read too)")
      ->required();
  cmd->add_option("--start", o->start, "Start pose x,y,yaw (m, m, rad; map frame)")->required();
  cmd->add_option("--goal", o->goal, "Goal pose x,y,yaw (m, m, rad; map frame)")->required();
  cmd->add_option("--out", o->out, "Output folder (path.csv, path.geojson, plan.png, summary.json)")
      ->required();
  cmd->add_option(
         "--robot", o->robot,
         "Robot YAML (length_m, width_m, min_turn_radius_m, ...; see "
         "config/robot_seed004.yaml); default: the seed's 0.93 x 0.58 m chassis, R_min 1 m")
      ->check(CLI::ExistingFile);
  cmd->add_option("--radius", o->radius_m,
                  "Minimum turning radius (m); default: the robot's min_turn_radius_m")
      ->check(real_in(0.1, 100.0));
  cmd->add_option("--budget-ms", o->budget_ms, "Time budget of the plan (ms)")
      ->capture_default_str()
      ->check(real_in(1.0, 600000.0));
  cmd->add_option("--weight", o->weight,
                  "Heuristic weight: 1 searches most thoroughly (near the cheapest path of its "
                  "lattice); above 1 it expands fewer nodes for a path up to this many times "
                  "costlier")
      ->capture_default_str()
      ->check(real_in(1.0, 10.0));
  cmd->add_option("--late-expansions", o->late_expansions,
                  "A search still going after this many expansions goes on at weight 1.5 (the "
                  "slowest plans, near a goal heading hard to meet, finish sooner); 0: never; "
                  "never at --weight 1")
      ->capture_default_str()
      ->check(whole_in(0, 100000000));
  cmd->add_flag("--no-unknown{false}", o->allow_unknown, "Never drive over unknown cells");
  cmd->add_flag("--no-smooth", o->no_smooth, "Return the search's path without smoothing");
  cmd->add_flag("-f,--force", o->force, "Replace existing output files");
  cmd->callback([o] { run(*o); });
}

}  // namespace fieldlidar::app
