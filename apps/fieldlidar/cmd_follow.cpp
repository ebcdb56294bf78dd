// fieldlidar follow: the seed 000 closed loop in simulation. A simulated mower follows its
// operator around a lawn (simulated scans -> ground -> clusters -> legs -> tracker -> controller ->
// mower motion) and records the lawn boundary.

#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "fieldlidar/core/error.hpp"
#include "fieldlidar/core/geo_origin.hpp"
#include "fieldlidar/io/file_util.hpp"
#include "fieldlidar/loops/closed_loop.hpp"
#include "follow_job.hpp"
#include "support/canvas.hpp"
#include "support/legs_runner.hpp"
#include "support/option_checks.hpp"
#include "support/warnings.hpp"

namespace fieldlidar::app {

namespace {

namespace fs = std::filesystem;

void write_text(const fs::path& path, const std::string& text, bool force) {
  io::write_file_atomic(path, text, force);
}

nlohmann::json config_json(const follow::FollowConfig& c) {
  nlohmann::json j;
  j["L_s_m"] = c.safety.safe_distance_m;
  j["L_m_m"] = c.safety.max_distance_m;
  const auto& d = c.drive;
  j["drive"] = {
      {"track_width_m", d.track_width_m},   {"wheel_diameter_m", d.wheel_diameter_m},
      {"gear_ratio", d.gear_ratio},         {"max_speed_m_s", d.max_speed_m_s},
      {"max_accel_m_s2", d.max_accel_m_s2}, {"max_wheel_speed_m_s", d.max_wheel_speed_m_s},
      {"max_dv_m_s", d.max_dv_m_s},         {"follow_distance_m", d.follow_distance_m},
      {"speed_gain_1_s", d.speed_gain_1_s}, {"lateral_weight_k_p", d.lateral_weight},
      {"prediction_s", d.prediction_s},     {"trail_spacing_m", d.trail_spacing_m}};
  const auto& l = c.legs;
  j["legs"] = {{"delta_c", l.curve_max},
               {"L_min_m", l.path_min_m},
               {"L_max_m", l.path_max_m},
               {"dist_max_m", l.pair_distance_max_m},
               {"S_s_m", l.range_min_m},
               {"S_m_m", l.range_max_m},
               {"min_rings", l.min_rings},
               {"segment_jump_m", l.segment_jump_m},
               {"path_step_m", l.path_step_m},
               {"smooth_window", l.smooth_window},
               {"chord_max_m", l.use_chord_max ? l.chord_max_m : -1.0},
               {"leg_height_band_m", {c.leg_height_min_m, c.leg_height_max_m}}};
  const auto& t = c.tracker;
  j["tracker"] = {{"accel_sigma_m_s2", t.accel_sigma_m_s2},
                  {"measurement_sigma_m", t.measurement_sigma_m},
                  {"gate_chi2", t.gate_chi2},
                  {"confirm_hits", t.confirm_hits},
                  {"coast_frames", t.coast_frames},
                  {"delete_after_miss_s", t.delete_after_miss_s}};
  j["boundary"] = {{"record_spacing_m", c.boundary.record_spacing_m},
                   {"simplify_tolerance_m", c.boundary.simplify_tolerance_m}};
  return j;
}

/// Points of the recording frame placed in the world (the lawn scene).
std::vector<Eigen::Vector2d> in_world(const Pose& T_world_frame,
                                      const std::vector<Eigen::Vector2d>& pts) {
  std::vector<Eigen::Vector2d> out;
  out.reserve(pts.size());
  for (const auto& p : pts)
    out.push_back((T_world_frame * Eigen::Vector3d(p.x(), p.y(), 0)).head<2>());
  return out;
}

void write_picture(const fs::path& path, const sim::Scene& scene, const loops::ClosedLoopResult& r,
                   const std::string& title, bool force) {
  TopDownCanvas canvas(scene.min_m(), scene.max_m(), 1400);
  const Pose& T = r.T_world_frame;
  // Lawn: the operator's true loop, then what the mower did and recorded.
  const auto loop = in_world(T, r.operator_loop);
  canvas.polyline(loop, {0.55, 0.8, 0.55}, 10.0, true);
  canvas.polyline(loop, {0.1, 0.55, 0.1}, 1.5, true);
  for (const auto& p : in_world(T, r.trail)) canvas.dot(p, {0.2, 0.4, 0.95}, 1.5);
  canvas.polyline(in_world(T, r.mower_path), {0.1, 0.1, 0.1}, 1.0);
  canvas.polyline(in_world(T, r.boundary.vertices), {0.85, 0.15, 0.1}, 2.5, r.boundary.closed);
  for (const auto& x : r.boundary.self_intersections)
    canvas.circle(in_world(T, {x.point_m}).front(), 0.4, {0.9, 0.0, 0.6}, 2.0);
  if (!r.rows.empty()) {
    const auto& first = r.rows.front();
    canvas.arrow(in_world(T, {{first.mower_x, first.mower_y}}).front(), first.mower_yaw + yaw_of(T),
                 1.5, {0, 0, 0});
  }
  canvas.legend({{"operator's true loop", {0.1, 0.55, 0.1}},
                 {"operator estimate (trail)", {0.2, 0.4, 0.95}},
                 {"mower path", {0.1, 0.1, 0.1}},
                 {"recorded boundary", {0.85, 0.15, 0.1}}});
  canvas.title(title);
  canvas.save_png(path, force);
}

/// "0.123 m", or "n/a" for a distance the run was too short to measure (no boundary: inf).
std::string metres_or_na(double m) {
  return std::isfinite(m) ? fmt::format("{:.3f} m", m) : std::string("n/a");
}

}  // namespace

void run_follow(const FollowOptions& o) {
  if (!o.replay.empty()) return run_follow_replay(o);
  if (o.scene != "lawn") throw Error("--scene '" + o.scene + "': only 'lawn' is supported");
  const auto scenario = loops::scenario_from_string(o.scenario);
  if (!scenario)
    throw Error("--scenario '" + o.scenario +
                "': expected default, crossing, stop, fast, occluded, standing-start or rough");
  const auto pose_source = loops::pose_source_from_string(o.pose_source);
  if (!pose_source)
    throw Error("--pose-source '" + o.pose_source + "': expected odometry or truth");
  const auto sensor = SensorModel::preset(o.sensor);
  if (!sensor) throw Error("--sensor '" + o.sensor + "': unknown sensor preset");
  std::optional<GeoOrigin> origin;
  if (!o.origin.empty()) origin = parse_geo_origin(o.origin, "--origin");
  loops::ClosedLoopConfig cfg;
  cfg.pose_source = *pose_source;
  std::string detector;
  if (sensor->kind == SensorModel::Kind::kPlanar2D) {
    // A 2D laser at leg height: the 2D leg pipeline with the shipped (or given) detector.
    LegsRunOptions lo;
    lo.input = "--sensor " + o.sensor;
    lo.config = o.legs_config;
    const LegsRunner legs(lo);
    cfg.legs_2d = legs.config_2d();
    detector = legs.detector_summary();
  } else if (!o.legs_config.empty()) {
    throw Error("--legs-config: only for 2D scans (--sensor laser2d, or --replay of 2D scans)");
  }
  if (o.target_id >= 0) cfg.follow.target_id = std::uint32_t(o.target_id);
  if (o.max_time_s > 0) cfg.max_time_s = o.max_time_s;
  if (o.safe_distance_m > 0) cfg.follow.safety.safe_distance_m = o.safe_distance_m;
  if (o.max_distance_m > 0) cfg.follow.safety.max_distance_m = o.max_distance_m;
  require(cfg.follow.safety.safe_distance_m < cfg.follow.safety.max_distance_m, "--safe-distance",
          fmt::format("{} m must be below --max-distance {} m", cfg.follow.safety.safe_distance_m,
                      cfg.follow.safety.max_distance_m));
  const fs::path dir(o.out);
  if (fs::exists(dir) && !fs::is_directory(dir))
    throw Error("--out " + o.out + ": exists and is not a folder");
  const fs::path geojson = dir / "boundary.geojson", csv = dir / "boundary.csv",
                 log = dir / "follow_log.csv", summary = dir / "summary.json",
                 png = dir / "follow.png";
  if (fs::is_directory(dir))
    for (const auto& p : {geojson, csv, log, summary, png}) io::check_writable(p, o.force);

  const auto scene = sim::make_lawn_scene(loops::lawn_config(*scenario), o.seed);
  const auto r = loops::run_closed_loop(scene, *sensor, cfg);
  if (o.target_id >= 0 && !r.first_target_id)
    throw Error(
        fmt::format("--target-id {}: no person track of that id appeared in {} frames "
                    "({:.1f} s); nothing written (leave it out to follow the person ahead)",
                    o.target_id, r.rows.size(), r.duration_s));
  const auto shape = follow::boundary_shape(r.boundary);
  if (shape != follow::BoundaryShape::kPolygon)
    warn(fmt::format("the boundary is not a closed polygon ({}); {} holds it as a LineString",
                     follow::to_string(shape), geojson.string()));
  fs::create_directories(dir);
  for (const auto& p : {geojson, csv, log, summary, png}) io::check_writable(p, o.force);

  const bool odometry = r.pose_source == loops::PoseSource::kOdometry;
  write_text(geojson, follow::boundary_geojson(r.boundary, odometry ? "odometry" : "world", origin),
             o.force);
  write_text(csv, follow::boundary_csv(r.boundary), o.force);
  write_text(log, loops::log_csv(r.rows), o.force);
  nlohmann::json s;
  s["scene"] = o.scene;
  s["scenario"] = o.scenario;
  s["sensor"] = sensor->name;
  if (!detector.empty()) s["detector"] = detector;
  s["seed"] = o.seed;
  s["frames"] = r.rows.size();
  s["duration_s"] = r.duration_s;
  s["stopped_by_command"] = r.stopped_by_command;
  s["pose_source"] = loops::to_string(r.pose_source);
  s["frame"] = odometry ? "odometry (the lidar pose of the first sweep), x-y in metres"
                        : "world (simulated lawn), x-y in metres";
  const Eigen::Vector3d frame_origin = r.T_world_frame.translation();
  s["frame_in_world"] = {{"x_m", frame_origin.x()},
                         {"y_m", frame_origin.y()},
                         {"yaw_deg", yaw_of(r.T_world_frame) * 180 / M_PI}};
  s["boundary_shape"] = follow::to_string(shape);
  s["metrics"] = {{"boundary_mean_distance_m", r.boundary_error.mean_m},
                  {"boundary_hausdorff_m", r.boundary_error.hausdorff_m},
                  {"boundary_vertices", r.boundary.vertices.size()},
                  {"boundary_area_m2", r.boundary.area_m2},
                  {"boundary_perimeter_m", r.boundary.perimeter_m},
                  {"self_intersections", r.boundary.self_intersections.size()},
                  {"frames_following", r.frames_following},
                  {"frames_moving_below_L_s", r.frames_moving_too_close},
                  {"target_id", r.first_target_id ? std::int64_t(*r.first_target_id) : -1},
                  {"target_switches", r.target_switches},
                  {"frames_target_chosen", r.frames_target_chosen},
                  {"frames_target_held", r.frames_target_held},
                  {"frames_target_estimate_off", r.frames_target_off},
                  {"occlusions", r.occlusions},
                  {"max_stop_delay_frames", r.max_stop_delay_frames},
                  {"max_resume_delay_frames", r.max_resume_delay_frames},
                  {"resumed_after_every_occlusion", r.resumed_after_every_occlusion},
                  {"mean_perception_ms", r.mean_perception_ms}};
  if (const auto& a = r.odometry_accuracy)
    s["odometry"] = {{"ate_rmse_m", a->ate_unaligned.translation_m.rmse},
                     {"ate_max_m", a->ate_unaligned.translation_m.max},
                     {"ate_se3_aligned_rmse_m", a->ate_se3.translation_m.rmse},
                     {"rpe_translation_mean_m", a->rpe.translation_m.mean},
                     {"rpe_rotation_mean_deg", a->rpe.rotation_deg.mean},
                     {"path_length_m", a->estimate_path_m},
                     {"true_path_length_m", a->reference_path_m},
                     {"unregistered_frames", r.odometry_unregistered},
                     {"degenerate_frames", r.odometry_degenerate},
                     {"mean_ms_per_frame", r.mean_odometry_ms}};
  s["config"] = config_json(cfg.follow);
  write_text(summary, s.dump(2) + "\n", o.force);
  write_picture(png, scene, r,
                fmt::format("fieldlidar follow: lawn, {}, {}, {} poses ({} frames)", o.scenario,
                            sensor->name, loops::to_string(r.pose_source), r.rows.size()),
                o.force);
  fmt::print(
      "follow: {} frames ({:.1f} s), {}, {} poses; boundary {} vertices, {:.1f} m2, vs walked loop "
      "mean {}, Hausdorff {}; {} self-intersections; target id {} switches {}; frames moving below "
      "L_s {}\n",
      r.rows.size(), r.duration_s, r.stopped_by_command ? "stopped at the start" : "time limit",
      loops::to_string(r.pose_source), r.boundary.vertices.size(), r.boundary.area_m2,
      metres_or_na(r.boundary_error.mean_m), metres_or_na(r.boundary_error.hausdorff_m),
      r.boundary.self_intersections.size(),
      r.first_target_id ? std::int64_t(*r.first_target_id) : -1, r.target_switches,
      r.frames_moving_too_close);
  if (const auto& a = r.odometry_accuracy)
    fmt::print("odometry: ATE {:.3f} m (max {:.3f} m) along {:.1f} m, {:.1f} ms per frame\n",
               a->ate_unaligned.translation_m.rmse, a->ate_unaligned.translation_m.max,
               a->reference_path_m, r.mean_odometry_ms);
  fmt::print("wrote {}\n", dir.string());
}

void add_follow_command(CLI::App& app) {
  auto o = std::make_shared<FollowOptions>();
  auto* cmd = app.add_subcommand(
      "follow", "Simulate the mower following its operator and recording the lawn boundary");
  cmd->add_option("--scene", o->scene, "Simulated scene (lawn)")->capture_default_str();
  cmd->add_option("--sensor", o->sensor,
                  "Sensor preset: a multi-beam LiDAR (vlp16, ...) or laser2d, a planar 2D laser at "
                  "the mower's 0.45 m mount (270 deg, 0.35 deg steps, 10 Hz) seen through the 2D "
                  "leg pipeline")
      ->capture_default_str();
  cmd->add_option("--scenario", o->scenario,
                  "default, crossing, stop, fast, occluded, standing-start or rough")
      ->capture_default_str();
  cmd->add_option("--seed", o->seed, "Scene seed")
      ->capture_default_str()
      ->check(whole_in(0, 9223372036854775807LL));
  cmd->add_option("--target-id", o->target_id,
                  "Track id of the person to follow (default: the person ahead at the start); an "
                  "id that never appears is an error")
      ->check(whole_in(0, 4294967295LL));
  cmd->add_option("--max-time", o->max_time_s,
                  "Time limit in s (default: from the lap length); a lap cut short is written as "
                  "an open LineString")
      ->check(real_above(0, 86400));
  cmd->add_option("--safe-distance", o->safe_distance_m, "L_s in m (default 1.2)")
      ->check(real_above(0, 100));
  cmd->add_option("--max-distance", o->max_distance_m, "L_m in m (default 7.0)")
      ->check(real_above(0, 100));
  cmd->add_option("--origin", o->origin,
                  "LAT,LON[,HEADING_DEG]: WGS84 position of the boundary frame's origin (the "
                  "mower's start with --pose-source odometry) and compass bearing of its +x axis, "
                  "default 90 = x east): boundary.geojson in longitude/"
                  "latitude as RFC 7946 asks (tangent plane: 1 mm error at 100 m, 0.1 m at 1 km, "
                  "at 48 deg latitude)");
  cmd->add_option("--pose-source", o->pose_source,
                  "The mower's pose: odometry (LiDAR + IMU + wheels; with --sensor laser2d wheels "
                  "and IMU) or truth (the simulator's)")
      ->capture_default_str();
  auto* replay = cmd->add_option(
      "--replay", o->replay,
      "A ROS1 bag (or a simulate folder) to replay instead of simulating: perception, "
      "tracking, target choice "
      "and controller on the recorded scans, the robot's motion from the recording "
      "(commands logged, not applied); writes follow_log.csv, summary.json and "
      "follow.png");
  cmd->add_option("--topic", o->topic, "With --replay: the scan topic (default: the only one)")
      ->needs(replay);
  cmd->add_option("--odom", o->odom_topic,
                  "With --replay: nav_msgs/Odometry topic of the bag giving the robot's motion, or "
                  "a TUM pose file of the sensor (e.g. a simulate folder's poses_tum.txt) "
                  "(default: the robot stands still)")
      ->needs(replay);
  cmd->add_option("--mount", o->mount,
                  "With --replay: the sensor's mount on the base X,Y,Z,ROLL,PITCH,YAW (m, deg; "
                  "e.g. 0.2,0,0.3,180,0,0 for a laser hung upside down), for a recording without "
                  "one (default: the bag's /tf with --odom; else a 3D sweep levelled by its "
                  "ground, a 2D laser taken as upright)")
      ->expected(6)
      ->delimiter(',')
      ->needs(replay);
  cmd->add_option("--rate", o->rate_hz,
                  "With --replay: stamp the frames at this rate (Hz) from the first one's stamp, "
                  "for frames without a clock (a folder of frames with no times.txt in or beside "
                  "it)")
      ->check(real_above(0, 1e4))
      ->needs(replay);
  cmd->add_option("--legs-config", o->legs_config,
                  "2D scans (--replay of a 2D laser, or --sensor laser2d): leg detector YAML and "
                  "its optional `tracker:` map (default: the shipped legs_2d.yaml)");
  cmd->add_option("--out", o->out, "Output folder")->required();
  cmd->add_flag("--force", o->force, "Overwrite existing output files");
  cmd->callback([o] { run_follow(*o); });
}

}  // namespace fieldlidar::app
