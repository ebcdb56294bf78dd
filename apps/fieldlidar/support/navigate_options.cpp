#include "support/navigate_options.hpp"

#include <vector>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/terrain/robot_config.hpp"
#include "support/option_checks.hpp"

namespace fieldlidar::app {
namespace {

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

}  // namespace

void add_navigate_options(CLI::App& cmd, NavigateOptions& o) {
  cmd.add_option("--scene", o.scene, "Simulated scene (terrain, 60 x 40 m)")->capture_default_str();
  cmd.add_option("--seed", o.seed, "Scene seed")
      ->capture_default_str()
      ->check(whole_in(0, 9223372036854775807LL));
  cmd.add_option("--noise-seed", o.noise_seed,
                 "Seed of the simulated sensor's range noise (the scene stays the --seed one)")
      ->capture_default_str()
      ->check(whole_in(0, 9223372036854775807LL));
  cmd.add_option("--start", o.start,
                 "Start pose x,y,yaw (m, m, rad; scene frame); default: the scene route's start");
  cmd.add_option("--goal", o.goal,
                 "Goal pose x,y,yaw (m, m, rad; scene frame); default: the scene route's end");
  cmd.add_option("--sensor", o.sensor,
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
  cmd.add_option("--robot", o.robot,
                 "Robot YAML (sizes, slope and step limits, min_turn_radius_m; see "
                 "config/robot_seed004.yaml); default: the seed's 0.93 x 0.58 m chassis")
      ->check(CLI::ExistingFile);
  cmd.add_option("--pairs", o.pairs,
                 "File of start/goal pairs, one per line: name,sx,sy,syaw,gx,gy,gyaw[,expect] "
                 "(m, rad; expect arrived or unreachable): each run in DIR/name, the table in "
                 "DIR/pairs.csv; fails when a pair does not end as expected")
      ->check(CLI::ExistingFile);
  cmd.add_option("--speed", o.speed_m_s, "Cruise speed (m/s)")
      ->capture_default_str()
      ->check(real_above(0, 5));
  cmd.add_option("--seen-no-ground", o.seen_no_ground_points,
                 "A cell with this many returns, its neighbours seen, but no ground is "
                 "impassable (a slope too steep for the ground segmentation); 0: unknown")
      ->capture_default_str()
      ->check(whole_in(0, 1000000));
  cmd.add_option("--drop-band", o.drop_band_max_m,
                 "Cells never seen on a line between ground cells this close (m) whose heights "
                 "differ by more than the robot's max step are impassable (the foot of a step "
                 "down, hidden by its lip); 0: off")
      ->capture_default_str()
      ->check(real_in(0, 20));
  cmd.add_option("--drop-slope", o.drop_min_slope_deg,
                 "... and whose heights differ by a slope steeper than this (deg)")
      ->capture_default_str()
      ->check(real_in(0, 89));
  cmd.add_option("--drop-radius", o.drop_radius_m,
                 "... looked for this far from the robot (m), beyond its blind disk")
      ->capture_default_str()
      ->check(real_in(0, 100));
  cmd.add_option("--blind-drops", o.blind_drop_clear_m,
                 "Cells never seen from this distance (m) of the robot out to the first ground "
                 "beyond its blind disk are impassable when that ground lies lower than the "
                 "robot's by more than its max step and does not lead back up to it (a "
                 "terrace's edge beside the start); 0: off")
      ->capture_default_str()
      ->check(real_in(0, 10));
  cmd.add_option("--tilt-stop", o.tilt_stop_deg,
                 "Tilted more than this (deg) while driving, the robot stops, takes the ground "
                 "under the front of its footprint as impassable and plans again; 0: off")
      ->capture_default_str()
      ->check(real_in(0, 90));
  cmd.add_option("--guess-looks", o.guess_looks,
                 "Before a goal cut off only by blind drops is reported unreachable, the robot "
                 "drives to see those cells from beyond its blind disk and plans again; at most "
                 "this many looks per drive (0: off)")
      ->capture_default_str()
      ->check(whole_in(0, 20));
  cmd.add_option("--cell", o.cell_m,
                 "Side of the map's cells (m): the robot's fused map, the truth it is scored on "
                 "and the planner's. The map's rules were chosen on 0.5 m cells; 0.25 plans gaps "
                 "and obstacle halos finer and drives shorter in about twice the time, but reads "
                 "ditches worse and needs sweeps from more than one pose to know level ground "
                 "between the rings (docs/navigate.md)")
      ->capture_default_str()
      ->check(real_in(0.1, 2));
  cmd.add_option("--margin", o.margin_m,
                 "Clearance (m) the planner keeps around the robot's rectangle")
      ->capture_default_str()
      ->check(real_in(0, 2));
  cmd.add_option("--shadow-radius", o.shadow_radius_m,
                 "Cells never seen within this distance (m) of the robot are shadows (hidden "
                 "ground: behind a rock, inside a ditch), planned as costly rather than unknown; "
                 "0: off")
      ->capture_default_str()
      ->check(real_in(0, 100));
  cmd.add_option("--unknown-tau", o.unknown_tau,
                 "Traversability the planner gives unknown cells (1: as good as the best known "
                 "ground; lower: unknown ground costs more, never forbidden)")
      ->capture_default_str()
      ->check(real_in(0.01, 1));
  cmd.add_option("--mast", o.mast_m,
                 "The LiDAR's height above the ground (m): its lowest beam meets level ground at "
                 "this height / tan(its angle below level), the blind disk round the robot "
                 "(4.5 m for a VLP-16 on 1.2 m). The map's rules were chosen on 1.2 m")
      ->capture_default_str()
      ->check(real_in(0.3, 3));
  cmd.add_option("--lidar-pitch", o.lidar_pitch_deg,
                 "The LiDAR mount's pitch (deg, positive: nose down; 0: level). Pitched "
                 "forward, the lowest beams meet the ground nearer ahead (10 deg: 2.6 m rather "
                 "than 4.5 m on a 1.2 m mast) and farther behind")
      ->capture_default_str()
      ->check(real_in(-15, 15));
  cmd.add_option("--start-look", o.start_look_rad,
                 "Cold start: turn in place this much (rad, counter-clockwise) before the first "
                 "plan, so a pitched LiDAR sweeps the ground round the start; 0: off. The turn "
                 "stops before a known-impassable cell, but the swept corners cross ground no "
                 "roof LiDAR sees")
      ->capture_default_str()
      ->check(real_in(0, 4 * M_PI));
  cmd.add_option("--start-creep", o.start_creep_m,
                 "Cold start: creep straight this far (m) before the first plan, so the ground "
                 "beside the start (in the LiDAR's blind disk) is seen from a second pose; -1: "
                 "one blind radius, 0: off")
      ->capture_default_str()
      ->check(real_in(-1, 20));
  cmd.add_option("--approach", o.approach_m,
                 "The last metres (m) driven to the start, straight back along its heading, "
                 "whose sweeps are in the map before the first plan (cut where the robot could "
                 "not have come from); 0: off, a cold start with the blind disk unseen")
      ->capture_default_str()
      ->check(real_in(0, 30));
  cmd.add_option("--blocked-goal-look", o.blocked_goal_look_m,
                 "A goal the map blocks while the robot is farther than this (m) is looked at "
                 "from the free pose nearest it (within 4 m) before it is called unreachable; 0: "
                 "off")
      ->capture_default_str()
      ->check(real_in(0, 1000));
  cmd.add_option("--start-disk-tau", o.start_disk_tau,
                 "Cells within the blind radius of the start no sweep has seen are planned at "
                 "this traversability (costlier than seen ground); 0: off, unknown")
      ->capture_default_str()
      ->check(real_in(0, 1));
  cmd.add_option("--pose-source", o.pose_source,
                 "The pose the robot maps, plans and drives by: truth, or odometry (LiDAR "
                 "odometry with IMU and wheels at every mapped sweep; the truth still scores)")
      ->capture_default_str();
  cmd.add_option("--replan-period", o.replan_period_s, "Re-plan at least this often (s)")
      ->capture_default_str()
      ->check(real_above(0, 3600));
  cmd.add_option("--switch-gain", o.switch_gain,
                 "A periodic re-plan is taken only when it costs this share less than the rest "
                 "of the current plan (blocked or costlier plans are re-planned as before); 0: "
                 "always taken")
      ->capture_default_str()
      ->check(real_in(0, 0.99));
  cmd.add_option("--max-time", o.max_time_s,
                 "Simulated time limit per run (s); default 40 s + 4 x straight distance / speed")
      ->check(real_above(0, 86400));
  cmd.add_option("--out", o.out,
                 "Output folder: plans.csv, plans.geojson, path.csv, navigate_log.csv, "
                 "summary.json, navigate.png")
      ->required();
  cmd.add_flag("-f,--force", o.force, "Replace existing output files");
}

loops::NavigateConfig navigate_config(const NavigateOptions& o) {
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
  return cfg;
}

}  // namespace fieldlidar::app
