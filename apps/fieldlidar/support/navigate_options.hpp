#pragma once
// The options of `fieldlidar navigate` and the loop configuration they set.

#include <cstdint>
#include <string>

#include <CLI/CLI.hpp>

#include "fieldlidar/loops/navigate.hpp"

namespace fieldlidar::app {

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

/// Adds every option of `navigate` but its subcommand's callback, with units, defaults and
/// valid ranges.
void add_navigate_options(CLI::App& cmd, NavigateOptions& o);

/// The loop's configuration the options ask for (the robot YAML read, the pose source named).
loops::NavigateConfig navigate_config(const NavigateOptions& o);

}  // namespace fieldlidar::app
