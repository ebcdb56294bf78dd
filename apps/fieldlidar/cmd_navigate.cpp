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
#include "fieldlidar/terrain/robot_config.hpp"
#include "support/navigate_output.hpp"
#include "support/navigate_tally.hpp"
#include "support/option_checks.hpp"
#include "support/output_folder.hpp"
#include "support/planar_paths.hpp"

namespace fieldlidar::app {
namespace {

namespace fs = std::filesystem;

struct NavigateOptions {
  std::string scene = "terrain", start, goal, robot, pairs, out, pose_source = "truth";
  std::string sensor = "vlp16";
  std::uint64_t seed = 0, noise_seed = loops::NavigateConfig{}.sim_seed;
  double max_time_s = 0, replan_period_s = loops::NavigateConfig{}.replan_period_s;
  double switch_gain = loops::NavigateConfig{}.replan_switch_gain;
  double speed_m_s = loops::NavigateConfig{}.follower.max_speed_m_s;
  int seen_no_ground_points = loops::NavigateConfig{}.seen_no_ground_points;
  double drop_band_max_m = loops::NavigateConfig{}.drop_band_max_m;
  double drop_min_slope_deg = loops::NavigateConfig{}.drop_min_slope_deg;
  double drop_radius_m = loops::NavigateConfig{}.drop_radius_m;
  double blind_drop_clear_m = loops::NavigateConfig{}.blind_drop_clear_m;
  double tilt_stop_deg = loops::NavigateConfig{}.tilt_stop_deg;
  int guess_looks = loops::NavigateConfig{}.guess_looks;
  double margin_m = loops::NavigateConfig{}.planner.map.footprint_margin_m;
  double cell_m = loops::NavigateConfig{}.fusion.layers.cell_m;
  double shadow_radius_m = loops::NavigateConfig{}.shadow_radius_m;
  double unknown_tau = loops::NavigateConfig{}.planner.map.unknown_tau;
  double start_creep_m = loops::NavigateConfig{}.start_creep_m;
  double approach_m = loops::NavigateConfig{}.approach_m;
  double start_disk_tau = loops::NavigateConfig{}.start_disk_tau;
  double blocked_goal_look_m = loops::NavigateConfig{}.blocked_goal_look_m;
  double lidar_pitch_deg = loops::NavigateConfig{}.lidar_pitch_deg;
  double mast_m = 1.2;
  double start_look_rad = loops::NavigateConfig{}.start_look_rad;
  bool force = false;
};

/// The sensor presets the loop drives with (loops::check_navigate_sensor): the spinning
/// multi-beam LiDARs, not the 2D lasers.
std::vector<std::string> navigate_presets() {
  std::vector<std::string> names;
  for (const auto& name : SensorModel::preset_names()) {
    try {
      loops::check_navigate_sensor(*SensorModel::preset(name));
    } catch (const Error&) {
      continue;
    }
    names.push_back(name);
  }
  return names;
}

std::string navigate_preset_list() {
  std::string list;
  for (const auto& k : navigate_presets()) list += (list.empty() ? "" : ", ") + k;
  return list;
}

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
  loops::NavigateConfig cfg;
  if (!o.robot.empty()) cfg.fusion.layers.robot = terrain::load_robot_config(o.robot);
  cfg.max_time_s = o.max_time_s;
  cfg.replan_period_s = o.replan_period_s;
  cfg.replan_switch_gain = o.switch_gain;
  cfg.follower.max_speed_m_s = o.speed_m_s;
  cfg.seen_no_ground_points = o.seen_no_ground_points;
  cfg.drop_band_max_m = o.drop_band_max_m;
  cfg.drop_min_slope_deg = o.drop_min_slope_deg;
  cfg.drop_radius_m = o.drop_radius_m;
  cfg.blind_drop_clear_m = o.blind_drop_clear_m;
  cfg.tilt_stop_deg = o.tilt_stop_deg;
  cfg.guess_looks = o.guess_looks;
  cfg.planner.map.footprint_margin_m = o.margin_m;
  cfg.fusion.layers.cell_m = o.cell_m;
  cfg.shadow_radius_m = o.shadow_radius_m;
  cfg.planner.map.unknown_tau = o.unknown_tau;
  cfg.start_creep_m = o.start_creep_m;
  cfg.approach_m = o.approach_m;
  cfg.start_disk_tau = o.start_disk_tau;
  cfg.blocked_goal_look_m = o.blocked_goal_look_m;
  cfg.lidar_pitch_deg = o.lidar_pitch_deg;
  cfg.start_look_rad = o.start_look_rad;
  cfg.sim_seed = o.noise_seed;
  const auto pose_source = loops::pose_source_from_string(o.pose_source);
  if (!pose_source)
    throw Error("--pose-source '" + o.pose_source + "': expected odometry or truth");
  cfg.pose_source = *pose_source;
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
  cmd->add_option("--scene", o->scene, "Simulated scene (terrain, 60 x 40 m)")
      ->capture_default_str();
  cmd->add_option("--seed", o->seed, "Scene seed")
      ->capture_default_str()
      ->check(whole_in(0, 9223372036854775807LL));
  cmd->add_option("--noise-seed", o->noise_seed,
                  "Seed of the simulated sensor's range noise (the scene stays the --seed one)")
      ->capture_default_str()
      ->check(whole_in(0, 9223372036854775807LL));
  cmd->add_option("--start", o->start,
                  "Start pose x,y,yaw (m, m, rad; scene frame); default: the scene route's start");
  cmd->add_option("--goal", o->goal,
                  "Goal pose x,y,yaw (m, m, rad; scene frame); default: the scene route's end");
  cmd->add_option("--sensor", o->sensor,
                  "The robot's LiDAR, a multi-beam preset (" + navigate_preset_list() +
                      ") on its --mast; its lowest beam sets the blind disk")
      ->capture_default_str()
      ->check(CLI::Validator(
          [](std::string& name) -> std::string {
            for (const auto& k : navigate_presets())
              if (name == k) return {};
            return "'" + name + "' is not a multi-beam preset (" + navigate_preset_list() + ")";
          },
          ""));
  cmd->add_option("--robot", o->robot,
                  "Robot YAML (sizes, slope and step limits, min_turn_radius_m; see "
                  "config/robot_seed004.yaml); default: the seed's 0.93 x 0.58 m chassis")
      ->check(CLI::ExistingFile);
  cmd->add_option("--pairs", o->pairs,
                  "File of start/goal pairs, one per line: name,sx,sy,syaw,gx,gy,gyaw[,expect] "
                  "(m, rad; expect arrived or unreachable): each run in DIR/name, the table in "
                  "DIR/pairs.csv; fails when a pair does not end as expected")
      ->check(CLI::ExistingFile);
  cmd->add_option("--speed", o->speed_m_s, "Cruise speed (m/s)")
      ->capture_default_str()
      ->check(real_above(0, 5));
  cmd->add_option("--seen-no-ground", o->seen_no_ground_points,
                  "A cell with this many returns, its neighbours seen, but no ground is "
                  "impassable (a slope too steep for the ground segmentation); 0: unknown")
      ->capture_default_str()
      ->check(whole_in(0, 1000000));
  cmd->add_option("--drop-band", o->drop_band_max_m,
                  "Cells never seen on a line between ground cells this close (m) whose heights "
                  "differ by more than the robot's max step are impassable (the foot of a step "
                  "down, hidden by its lip); 0: off")
      ->capture_default_str()
      ->check(real_in(0, 20));
  cmd->add_option("--drop-slope", o->drop_min_slope_deg,
                  "... and whose heights differ by a slope steeper than this (deg)")
      ->capture_default_str()
      ->check(real_in(0, 89));
  cmd->add_option("--drop-radius", o->drop_radius_m,
                  "... looked for this far from the robot (m), beyond its blind disk")
      ->capture_default_str()
      ->check(real_in(0, 100));
  cmd->add_option("--blind-drops", o->blind_drop_clear_m,
                  "Cells never seen from this distance (m) of the robot out to the first ground "
                  "beyond its blind disk are impassable when that ground lies lower than the "
                  "robot's by more than its max step and does not lead back up to it (a "
                  "terrace's edge beside the start); 0: off")
      ->capture_default_str()
      ->check(real_in(0, 10));
  cmd->add_option("--tilt-stop", o->tilt_stop_deg,
                  "Tilted more than this (deg) while driving, the robot stops, takes the ground "
                  "under the front of its footprint as impassable and plans again; 0: off")
      ->capture_default_str()
      ->check(real_in(0, 90));
  cmd->add_option("--guess-looks", o->guess_looks,
                  "Before a goal cut off only by blind drops is reported unreachable, the robot "
                  "drives to see those cells from beyond its blind disk and plans again; at most "
                  "this many looks per drive (0: off)")
      ->capture_default_str()
      ->check(whole_in(0, 20));
  cmd->add_option("--cell", o->cell_m,
                  "Side of the map's cells (m): the robot's fused map, the truth it is scored on "
                  "and the planner's. The map's rules were chosen on 0.5 m cells; 0.25 plans gaps "
                  "and obstacle halos finer and drives shorter in about twice the time, but reads "
                  "ditches worse and needs sweeps from more than one pose to know level ground "
                  "between the rings (docs/navigate.md)")
      ->capture_default_str()
      ->check(real_in(0.1, 2));
  cmd->add_option("--margin", o->margin_m,
                  "Clearance (m) the planner keeps around the robot's rectangle")
      ->capture_default_str()
      ->check(real_in(0, 2));
  cmd->add_option("--shadow-radius", o->shadow_radius_m,
                  "Cells never seen within this distance (m) of the robot are shadows (hidden "
                  "ground: behind a rock, inside a ditch), planned as costly rather than unknown; "
                  "0: off")
      ->capture_default_str()
      ->check(real_in(0, 100));
  cmd->add_option("--unknown-tau", o->unknown_tau,
                  "Traversability the planner gives unknown cells (1: as good as the best known "
                  "ground; lower: unknown ground costs more, never forbidden)")
      ->capture_default_str()
      ->check(real_in(0.01, 1));
  cmd->add_option("--mast", o->mast_m,
                  "The LiDAR's height above the ground (m): its lowest beam meets level ground at "
                  "this height / tan(its angle below level), the blind disk round the robot "
                  "(4.5 m for a VLP-16 on 1.2 m). The map's rules were chosen on 1.2 m")
      ->capture_default_str()
      ->check(real_in(0.3, 3));
  cmd->add_option("--lidar-pitch", o->lidar_pitch_deg,
                  "The LiDAR mount's pitch (deg, positive: nose down; 0: level). Pitched "
                  "forward, the lowest beams meet the ground nearer ahead (10 deg: 2.6 m rather "
                  "than 4.5 m on a 1.2 m mast) and farther behind")
      ->capture_default_str()
      ->check(real_in(-15, 15));
  cmd->add_option("--start-look", o->start_look_rad,
                  "Cold start: turn in place this much (rad, counter-clockwise) before the first "
                  "plan, so a pitched LiDAR sweeps the ground round the start; 0: off. The turn "
                  "stops before a known-impassable cell, but the swept corners cross ground no "
                  "roof LiDAR sees")
      ->capture_default_str()
      ->check(real_in(0, 4 * M_PI));
  cmd->add_option("--start-creep", o->start_creep_m,
                  "Cold start: creep straight this far (m) before the first plan, so the ground "
                  "beside the start (in the LiDAR's blind disk) is seen from a second pose; -1: "
                  "one blind radius, 0: off")
      ->capture_default_str()
      ->check(real_in(-1, 20));
  cmd->add_option("--approach", o->approach_m,
                  "The last metres (m) driven to the start, straight back along its heading, "
                  "whose sweeps are in the map before the first plan (cut where the robot could "
                  "not have come from); 0: off, a cold start with the blind disk unseen")
      ->capture_default_str()
      ->check(real_in(0, 30));
  cmd->add_option("--blocked-goal-look", o->blocked_goal_look_m,
                  "A goal the map blocks while the robot is farther than this (m) is looked at "
                  "from the free pose nearest it (within 4 m) before it is called unreachable; 0: "
                  "off")
      ->capture_default_str()
      ->check(real_in(0, 1000));
  cmd->add_option("--start-disk-tau", o->start_disk_tau,
                  "Cells within the blind radius of the start no sweep has seen are planned at "
                  "this traversability (costlier than seen ground); 0: off, unknown")
      ->capture_default_str()
      ->check(real_in(0, 1));
  cmd->add_option("--pose-source", o->pose_source,
                  "The pose the robot maps, plans and drives by: truth, or odometry (LiDAR "
                  "odometry with IMU and wheels at every mapped sweep; the truth still scores)")
      ->capture_default_str();
  cmd->add_option("--replan-period", o->replan_period_s, "Re-plan at least this often (s)")
      ->capture_default_str()
      ->check(real_above(0, 3600));
  cmd->add_option("--switch-gain", o->switch_gain,
                  "A periodic re-plan is taken only when it costs this share less than the rest "
                  "of the current plan (blocked or costlier plans are re-planned as before); 0: "
                  "always taken")
      ->capture_default_str()
      ->check(real_in(0, 0.99));
  cmd->add_option("--max-time", o->max_time_s,
                  "Simulated time limit per run (s); default 40 s + 4 x straight distance / speed")
      ->check(real_above(0, 86400));
  cmd->add_option("--out", o->out,
                  "Output folder: plans.csv, plans.geojson, path.csv, navigate_log.csv, "
                  "summary.json, navigate.png")
      ->required();
  cmd->add_flag("-f,--force", o->force, "Replace existing output files");
  cmd->callback([o] { run(*o); });
}

}  // namespace fieldlidar::app
