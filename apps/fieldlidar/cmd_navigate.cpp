// fieldlidar navigate [--scene terrain] [--seed N] [--start x,y,yaw] [--goal x,y,yaw]
// [--robot robot.yaml] [--pairs FILE] --out DIR: seed 004 in closed loop in the simulator
// (simulated VLP-16 scans -> fused traversability map -> Hybrid A* -> pure pursuit -> motion,
// re-planning as the map grows). One run, or every start/goal pair of a file with a table.

#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/file_util.hpp"
#include "fieldlidar/loops/navigate.hpp"
#include "fieldlidar/loops/navigate_pairs.hpp"
#include "fieldlidar/sim/scenes.hpp"
#include "support/navigate_options.hpp"
#include "support/navigate_output.hpp"
#include "support/navigate_tally.hpp"
#include "support/option_checks.hpp"
#include "support/output_folder.hpp"
#include "support/planar_paths.hpp"

namespace fieldlidar::app {
namespace {

namespace fs = std::filesystem;

/// The scene's route start (heading to its second waypoint) and end.
loops::NavigatePair default_pair(const sim::Scene& scene) {
  const auto& r = scene.robot_route();
  const auto yaw = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return std::atan2(b.y() - a.y(), b.x() - a.x());
  };
  const std::size_t n = r.size();
  return {"route",
          {r[0].x(), r[0].y(), yaw(r[0], r[1])},
          {r[n - 1].x(), r[n - 1].y(), yaw(r[n - 2], r[n - 1])},
          ""};
}

std::string row_text(const loops::NavigatePair& p, const loops::NavigateResult& r) {
  return fmt::format(
      "{:<14} {:<11} {:>8.1f} {:>8.1f} {:>6} {:>6} {:>6} {:>6.2f} {:>6} {:>6.2f} {:>7.1f} "
      "{:>7.1f}  {}",
      p.name, loops::to_string(r.outcome), r.driven_length_m,
      std::isfinite(r.truth_length_m) ? r.truth_length_m : 0.0,
      std::isfinite(r.length_ratio) ? fmt::format("{:.3f}", r.length_ratio) : "-", r.replans,
      r.frames_on_impassable, r.max_impassable_depth_m, r.frames_on_obstacles, r.min_obstacle_gap_m,
      r.duration_s, r.wall_s, r.reason);
}

void run(const NavigateOptions& o) {
  if (o.scene != "terrain") throw Error("--scene '" + o.scene + "': only 'terrain' is supported");
  require(o.pairs.empty() || (o.start.empty() && o.goal.empty()), "--pairs",
          "takes the starts and goals from the file: leave out --start and --goal");
  const loops::NavigateConfig cfg = navigate_config(o);
  const auto preset = SensorModel::preset(o.sensor);
  if (!preset) throw Error("navigate: --sensor: unknown preset '" + o.sensor + "'");
  const SensorModel& sensor = *preset;
  loops::check_navigate_sensor(sensor);
  sim::Scene scene = sim::make_terrain_scene({}, o.seed);
  scene.set_sensor_height_m(o.mast_m);
  std::vector<loops::NavigatePair> pairs;
  if (!o.pairs.empty()) {
    pairs = loops::read_navigate_pairs(o.pairs);
    // Each pair's run goes to DIR/name: a second pair of a name would fail on the first's files
    // after the first had run.
    std::set<std::string> names;
    for (const auto& p : pairs)
      if (!names.insert(p.name).second)
        throw Error("--pairs " + o.pairs + ": two pairs are named '" + p.name +
                    "' (each pair's run is written to DIR/name): rename one");
  } else {
    loops::NavigatePair p = default_pair(scene);
    if (!o.start.empty()) p.start = parse_pose(o.start, "--start");
    if (!o.goal.empty()) p.goal = parse_pose(o.goal, "--goal");
    pairs.push_back(p);
  }
  const fs::path out(o.out);
  if (fs::exists(out) && !fs::is_directory(out))
    throw Error("navigate: --out " + o.out + " exists and is not a folder");
  const bool many = !o.pairs.empty();
  std::vector<fs::path> files;
  for (const auto& p : pairs)
    for (const auto& f : navigate_files(many ? out / p.name : out)) files.push_back(f);
  if (many) files.push_back(out / "pairs.csv");
  for (const auto& f : files)
    if (fs::exists(f) && !o.force)
      throw Error("navigate: " + f.string() + " exists (use --force to replace it)");
  const std::string header =
      fmt::format("{:<14} {:<11} {:>8} {:>8} {:>6} {:>6} {:>6} {:>6} {:>6} {:>6} {:>7} {:>7}  {}",
                  "pair", "outcome", "driven_m", "truth_m", "ratio", "replan", "imp_fr", "depth",
                  "obs_fr", "gap_m", "sim_s", "wall_s", "reason");
  std::string table_csv =
      "pair,expect,outcome,driven_m,truth_plan_m,ratio,replans,frames_on_impassable,"
      "max_impassable_depth_m,frames_on_obstacles,min_obstacle_gap_m,max_tilt_deg,sim_s,wall_s,"
      "reason\n";
  std::vector<std::string> lines;
  NavigateTally tally;
  int mismatches = 0;
  const OutputFolder folder(out);  // gone again if the first drive is refused before any output
  for (const auto& p : pairs) {
    const fs::path dir = many ? out / p.name : out;
    const OutputFolder pair_folder(dir);
    for (const auto& f : navigate_files(dir)) io::check_writable(f, o.force);
    fmt::print(stderr, "navigate {}: ({:.1f}, {:.1f}, {:.2f}) -> ({:.1f}, {:.1f}, {:.2f}) ...\n",
               p.name, p.start.x_m, p.start.y_m, p.start.yaw_rad, p.goal.x_m, p.goal.y_m,
               p.goal.yaw_rad);
    const loops::NavigateResult r = loops::run_navigate(scene, sensor, p.start, p.goal, cfg);
    nlohmann::json extra = navigate_settings(cfg);
    extra.update({{"scene", o.scene},
                  {"seed", o.seed},
                  {"pair", p.name},
                  {"sensor", sensor.name},
                  {"mast_m", o.mast_m}});
    if (!p.expect.empty()) extra["expected"] = p.expect;
    write_navigate_run(dir, r, extra,
                       fmt::format("fieldlidar navigate: terrain seed {}, {}: {} ({:.1f} m driven, "
                                   "{} replans, {} frames on truth-impassable)",
                                   o.seed, p.name, loops::to_string(r.outcome), r.driven_length_m,
                                   r.replans, r.frames_on_impassable),
                       o.force);
    tally.add(r);
    const bool mismatch = !p.expect.empty() && p.expect != loops::to_string(r.outcome);
    mismatches += mismatch;
    lines.push_back(row_text(p, r) + (mismatch ? "  (expected " + p.expect + ")" : ""));
    fmt::print(stderr, "  {}\n", lines.back());
    table_csv += fmt::format(
        "{},{},{},{:.2f},{:.2f},{:.4f},{},{},{:.2f},{},{:.2f},{:.1f},{:.1f},{:.1f},\"{}\"\n",
        p.name, p.expect, loops::to_string(r.outcome), r.driven_length_m, r.truth_length_m,
        r.length_ratio, r.replans, r.frames_on_impassable, r.max_impassable_depth_m,
        r.frames_on_obstacles, r.min_obstacle_gap_m, r.max_tilt_deg, r.duration_s, r.wall_s,
        r.reason);
  }
  if (many) io::write_file_atomic(out / "pairs.csv", table_csv, o.force);
  fmt::print("{}\n", header);
  for (const auto& l : lines) fmt::print("{}\n", l);
  if (many) fmt::print("{}\n", tally.text());
  fmt::print("wrote {}\n", out.string());
  if (mismatches)
    throw Error(
        fmt::format("navigate: {} of {} pairs did not end as expected", mismatches, pairs.size()));
}

}  // namespace

void add_navigate_command(CLI::App& app) {
  auto o = std::make_shared<NavigateOptions>();
  auto* cmd = app.add_subcommand(
      "navigate",
      "Simulated off-road robot driving itself to a goal: LiDAR sweeps -> fused traversability "
      "map (true poses, or its own LiDAR odometry with --pose-source odometry) -> Hybrid A* -> "
      "pure pursuit, re-planning as the map grows");
  add_navigate_options(*cmd, *o);
  cmd->callback([o] { run(*o); });
}

}  // namespace fieldlidar::app
