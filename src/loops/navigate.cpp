// The navigate loop (seed 004 in closed loop): scan -> fused traversability map -> Hybrid A* ->
// pure pursuit -> motion, re-planning when the map blocks the path, makes it costlier, or a period
// has passed; the truth is only read to score the run (and to plan the reference path). This file:
// the loop's set-up and the checked entry point; its steps are in navigate_run.cpp,
// navigate_replan.cpp and navigate_sense.cpp.

#include "fieldlidar/loops/navigate.hpp"

#include <cmath>
#include <utility>

#include <fmt/core.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/terrain/robot_config.hpp"
#include "navigate_loop.hpp"

namespace fieldlidar::loops {
namespace detail {

namespace {

SensorModel on_mast(SensorModel sensor, double mast_m) {
  if (!(sensor.mounting_height_m > 0)) sensor.mounting_height_m = mast_m;
  return sensor;
}

}  // namespace

Loop::Loop(const sim::Scene& scene, const SensorModel& sensor, const NavigateConfig& config)
    : scene_(scene),
      sensor_(on_mast(sensor, scene.sensor_height_m())),
      cfg_(config),
      robot_(config.fusion.layers.robot),
      planner_cfg_(planning::planner_config_for(robot_, config.planner)),
      lidar_(scene, sensor, sim::SimConfig{.seed = config.sim_seed}),
      map_(config.fusion) {
  planning::FollowerConfig f = config.follower;
  f.min_turn_radius_m = robot_.min_turn_radius_m;
  follower_ = planning::PathFollower(f);
  area_ = GridGeometry::covering(scene.min_m(), scene.max_m(), config.fusion.layers.cell_m);
  mast_m_ = scene.sensor_height_m();
  if (sensor.min_altitude_rad() < -0.01) blind_radius_m_ = sensor.ground_reach_m(mast_m_);
}

}  // namespace detail

namespace {

bool finite(const planning::Pose2& p) {
  return std::isfinite(p.x_m) && std::isfinite(p.y_m) && std::isfinite(p.yaw_rad);
}

}  // namespace

void check_navigate_sensor(const SensorModel& sensor) {
  // A nodding 2D scanner has planes below the horizon too, but sweeps them over a second or more
  // and only ahead: the loop's blind disk and sweep-by-sweep fusion assume a spinning LiDAR.
  if (sensor.kind != SensorModel::Kind::kSpinning)
    throw Error("navigate: sensor " + sensor.name +
                " is a 2D laser, not a spinning multi-beam LiDAR: the loop maps the ground with "
                "one");
  if (sensor.rings() < 2 || !(sensor.beam_altitudes_rad.front() < -0.01))
    throw Error(fmt::format(
        "navigate: sensor {} has {} beam(s), the lowest at {:.1f} deg: the loop maps the ground "
        "with a multi-beam LiDAR whose lowest beam points below the horizon",
        sensor.name, sensor.rings(),
        sensor.rings() > 0 ? sensor.beam_altitudes_rad.front() * 180 / M_PI : 0.0));
}

NavigateResult run_navigate(const sim::Scene& scene, const SensorModel& sensor,
                            const planning::Pose2& start, const planning::Pose2& goal,
                            const NavigateConfig& config) {
  terrain::check_robot_config(config.fusion.layers.robot, "navigate: robot");
  if (!finite(start) || !finite(goal)) throw Error("navigate: start and goal must be finite");
  check_navigate_sensor(sensor);
  for (const auto& [name, p] : {std::pair{"start", start}, std::pair{"goal", goal}})
    if (p.x_m < scene.min_m().x() || p.y_m < scene.min_m().y() || p.x_m > scene.max_m().x() ||
        p.y_m > scene.max_m().y())
      throw Error(
          fmt::format("navigate: {} ({:.2f}, {:.2f}) m is off the scene", name, p.x_m, p.y_m));
  if (!(config.control_period_s > 0 && config.control_period_s <= 1.0) ||
      !(config.scan_period_s >= config.control_period_s && config.scan_period_s <= 10.0) ||
      !(config.replan_period_s > 0))
    throw Error(
        fmt::format("navigate: control_period_s must be in (0, 1] (is {}), scan_period_s in "
                    "[control_period_s, 10] (is {}) and replan_period_s > 0 (is {})",
                    config.control_period_s, config.scan_period_s, config.replan_period_s));
  if (!(config.replan_switch_gain >= 0.0 && config.replan_switch_gain < 1.0))
    throw Error(fmt::format("navigate: replan_switch_gain must be in [0, 1) (is {})",
                            config.replan_switch_gain));
  if (!(std::abs(config.lidar_pitch_deg) <= 30.0) || !(config.start_look_rad >= 0.0) ||
      !std::isfinite(config.start_look_rad) || !(config.look_yaw_rate_rad_s > 0.0))
    throw Error(fmt::format(
        "navigate: lidar_pitch_deg must be in [-30, 30] (is {}), start_look_rad finite and >= 0 "
        "(is {}), look_yaw_rate_rad_s > 0 (is {})",
        config.lidar_pitch_deg, config.start_look_rad, config.look_yaw_rate_rad_s));
  if (!(config.approach_m >= 0.0 && config.approach_m <= 100.0) ||
      !(config.approach_sweep_m > 0.0) ||
      !(config.escape_max_m >= 0.0 && config.escape_max_m <= 10.0) ||
      !(config.start_disk_tau >= 0.0 && config.start_disk_tau <= 1.0))
    throw Error(fmt::format(
        "navigate: approach_m must be in [0, 100] (is {}), approach_sweep_m > 0 (is "
        "{}), escape_max_m in [0, 10] (is {}) and start_disk_tau in [0, 1] (is {})",
        config.approach_m, config.approach_sweep_m, config.escape_max_m, config.start_disk_tau));
  if (!(config.blocked_goal_look_m >= 0.0) || !(config.blocked_goal_approach_m >= 0.0) ||
      !std::isfinite(config.blocked_goal_look_m) || !(config.blocked_goal_approach_m <= 20.0))
    throw Error(fmt::format(
        "navigate: blocked_goal_look_m must be finite and >= 0 (is {}), blocked_goal_approach_m "
        "in [0, 20] (is {})",
        config.blocked_goal_look_m, config.blocked_goal_approach_m));
  if (!(config.blind_drop_clear_m >= 0.0 && config.blind_drop_clear_m <= 10.0))
    throw Error(fmt::format("navigate: blind_drop_clear_m must be in [0, 10] (is {})",
                            config.blind_drop_clear_m));
  if (!(config.tilt_stop_deg >= 0.0 && config.tilt_stop_deg <= 90.0))
    throw Error(
        fmt::format("navigate: tilt_stop_deg must be in [0, 90] (is {})", config.tilt_stop_deg));
  if (!(config.guess_looks >= 0 && config.guess_looks <= 20) ||
      !(config.guess_look_margin_m >= 0.0 && config.guess_look_margin_m <= 10.0) ||
      !(config.guess_look_depth_m >= 0.0 && config.guess_look_depth_m <= 20.0))
    throw Error(fmt::format(
        "navigate: guess_looks must be in [0, 20] (is {}), guess_look_margin_m in [0, 10] (is "
        "{}), guess_look_depth_m in [0, 20] (is {})",
        config.guess_looks, config.guess_look_margin_m, config.guess_look_depth_m));
  if (!(config.retry_budget_factor >= 1.0 && config.retry_budget_factor <= 100.0) ||
      !(config.retry_lattice_cell_m >= 0.0 && config.retry_lattice_cell_m <= 10.0))
    throw Error(fmt::format(
        "navigate: retry_budget_factor must be in [1, 100] (is {}), retry_lattice_cell_m in [0, "
        "10] (is {})",
        config.retry_budget_factor, config.retry_lattice_cell_m));
  detail::Loop loop(scene, sensor, config);
  return loop.run(start, goal);
}

}  // namespace fieldlidar::loops
