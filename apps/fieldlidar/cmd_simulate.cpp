// fieldlidar simulate: frames, true poses, IMU, wheel odometry and scene truth from a procedural
// field scene, plus an optional top-down preview.

#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/cloud_file.hpp"
#include "fieldlidar/io/file_util.hpp"
#include "fieldlidar/io/kitti_bin.hpp"
#include "fieldlidar/io/label_file.hpp"
#include "fieldlidar/io/trajectory_io.hpp"
#include "fieldlidar/sim/lidar_simulator.hpp"
#include "fieldlidar/sim/motion.hpp"
#include "fieldlidar/sim/scenes.hpp"
#include "support/option_checks.hpp"
#include "support/progress_line.hpp"
#include "support/sim_preview.hpp"

namespace fieldlidar::app {

namespace {

namespace fs = std::filesystem;

constexpr long long kMaxSeed = 9223372036854775807LL;

struct SimulateOptions {
  std::string scene;
  std::string sensor = "vlp16";
  int frames = 10;
  std::uint64_t seed = 0;
  std::string out;
  bool preview = false;
  bool force = false;
  double noise_m = -1.0;
  double dropout = 0.0;
  double imu_rate_hz = 200.0;
  double odom_rate_hz = 50.0;
  double truth_resolution_m = 0.5;
  // Lawn scenario options.
  bool crossing = false, stops = false, too_fast = false, behind_shed = false, waits = false;
  int extra_walkers = 0;
  double rough = 0;
  double operator_speed = 1.0;
};

/// Refuses a run whose frames would not fit on the disk under `dir`, judged by its first sweep
/// (`points` returns): each return takes 44 bytes over its three files (KITTI .bin 16, .label 4,
/// binary PCD 24), and later sweeps may hold a fifth more.
void check_disk_space(const fs::path& dir, std::size_t points, int frames) {
  const double bytes = 1.2 * 44.0 * double(points) * double(frames);
  fs::path existing = fs::absolute(dir);
  while (!fs::exists(existing) && existing.has_parent_path() && existing != existing.parent_path())
    existing = existing.parent_path();
  std::error_code ec;
  const fs::space_info space = fs::space(existing, ec);
  if (!ec && bytes > double(space.available))
    throw Error(fmt::format(
        "--frames {}: about {:.1f} GB to write ({} returns in the first sweep), and {} has "
        "{:.1f} GB free; simulate fewer frames or write elsewhere",
        frames, bytes / 1e9, points, existing.string(), double(space.available) / 1e9));
}

void write_text(const fs::path& path, const std::string& text, bool force) {
  io::write_file_atomic(path, text.data(), text.size(), force);
}

sim::Scene build_scene(const SimulateOptions& o, sim::SceneKind kind) {
  if (kind != sim::SceneKind::kLawn) return sim::make_scene(kind, o.seed);
  sim::LawnConfig cfg;
  cfg.second_person_crossing = o.crossing;
  cfg.operator_stops = o.stops;
  cfg.operator_too_fast = o.too_fast;
  cfg.operator_behind_shed = o.behind_shed;
  cfg.operator_waits_at_start = o.waits;
  cfg.extra_walkers = o.extra_walkers;
  cfg.roughness_m = o.rough;
  cfg.operator_speed_m_s = o.operator_speed;
  return sim::make_lawn_scene(cfg, o.seed);
}

std::string imu_csv(const std::vector<sim::ImuSample>& imu) {
  std::string s =
      "stamp_s,gyro_x_rad_s,gyro_y_rad_s,gyro_z_rad_s,accel_x_m_s2,accel_y_m_s2,accel_z_m_s2\n";
  for (const auto& m : imu)
    s += fmt::format("{:.6f},{:.6f},{:.6f},{:.6f},{:.5f},{:.5f},{:.5f}\n", m.stamp_s,
                     m.gyro_rad_s.x(), m.gyro_rad_s.y(), m.gyro_rad_s.z(), m.accel_m_s2.x(),
                     m.accel_m_s2.y(), m.accel_m_s2.z());
  return s;
}

std::string odom_csv(const std::vector<sim::WheelOdometrySample>& odo) {
  std::string s =
      "stamp_s,left_m_s,right_m_s,left_rad_s,right_rad_s,linear_m_s,yaw_rate_rad_s,dr_x_m,dr_y_m,"
      "dr_yaw_rad\n";
  for (const auto& m : odo)
    s += fmt::format("{:.6f},{:.5f},{:.5f},{:.5f},{:.5f},{:.5f},{:.5f},{:.4f},{:.4f},{:.5f}\n",
                     m.stamp_s, m.left_m_s, m.right_m_s, m.left_rad_s, m.right_rad_s, m.linear_m_s,
                     m.yaw_rate_rad_s, m.dead_reckoned.translation().x(),
                     m.dead_reckoned.translation().y(), yaw_of(m.dead_reckoned));
  return s;
}

std::string truth_trees_csv(const std::vector<sim::TreeTruth>& trees) {
  std::string s =
      "id,base_x_m,base_y_m,base_z_m,axis_x,axis_y,axis_z,dbh_m,height_m,taper_m_per_m,leaning,"
      "forked,"
      "fork_height_m,low_branches\n";
  for (const auto& t : trees)
    s += fmt::format(
        "{},{:.4f},{:.4f},{:.4f},{:.6f},{:.6f},{:.6f},{:.4f},{:.3f},{:.5f},{},{},{:.3f},{}\n", t.id,
        t.base_m.x(), t.base_m.y(), t.base_m.z(), t.axis.x(), t.axis.y(), t.axis.z(), t.dbh_m,
        t.height_m, t.taper_m_per_m, int(t.leaning), int(t.forked), t.fork_height_m,
        t.low_branches);
  return s;
}

/// nav2 map_server map: passable 254 (free), impassable 0 (occupied); top row = largest y.
void write_terrain_truth(const fs::path& dir, const Grid2D& truth, bool force) {
  const auto& g = truth.geometry();
  const auto passable = truth.layer("passable");
  std::string pgm =
      fmt::format("P5\n# fieldlidar terrain truth: 254 passable, 0 impassable\n{} {}\n255\n",
                  g.width, g.height);
  for (int iy = g.height - 1; iy >= 0; --iy)
    for (int ix = 0; ix < g.width; ++ix)
      pgm.push_back(static_cast<char>(passable[g.linear_index(ix, iy)] > 0.5f ? 254 : 0));
  write_text(dir / "terrain_truth.pgm", pgm, force);
  write_text(
      dir / "terrain_truth.yaml",
      fmt::format("image: terrain_truth.pgm\nmode: trinary\nresolution: {}\norigin: [{}, {}, 0.0]\n"
                  "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n",
                  g.resolution_m, g.origin_m.x(), g.origin_m.y()),
      force);
  std::string csv = "ix,iy,x_m,y_m,elevation_m,slope_deg,step_m,obstacle,passable\n";
  for (int iy = 0; iy < g.height; ++iy)
    for (int ix = 0; ix < g.width; ++ix) {
      const auto c = g.cell_center(ix, iy);
      csv += fmt::format("{},{},{:.3f},{:.3f},{:.3f},{:.2f},{:.3f},{},{}\n", ix, iy, c.x(), c.y(),
                         truth.at("elevation", ix, iy), truth.at("slope_deg", ix, iy),
                         truth.at("step_m", ix, iy), int(truth.at("obstacle", ix, iy)),
                         int(truth.at("passable", ix, iy)));
    }
  write_text(dir / "terrain_truth.csv", csv, force);
}

void run_simulate(const SimulateOptions& o) {
  const auto kind = sim::scene_kind_from_string(o.scene);
  if (!kind)
    throw Error("--scene: unknown scene '" + o.scene + "' (lawn, greenhouse, forest, terrain)");
  const auto sensor = SensorModel::preset(o.sensor);
  if (!sensor) throw Error("--sensor: unknown preset '" + o.sensor + "'");
  const fs::path dir(o.out);
  if (fs::exists(dir / "poses.txt") && !o.force)
    throw Error((dir / "poses.txt").string() +
                ": exists (a previous simulation); pass --force to replace it");
  if (fs::is_directory(dir))  // before any frame: outputs that may not be replaced
    for (const char* name :
         {"poses.txt", "times.txt", "poses_tum.txt", "imu.csv", "odom.csv", "scene.json",
          "velodyne/000000.bin", "labels/000000.label", "pcd/000000.pcd"})
      if (fs::is_directory((dir / name).parent_path())) io::check_writable(dir / name, o.force);

  const auto t_start = std::chrono::steady_clock::now();
  const sim::Scene scene = build_scene(o, *kind);
  const double period = sensor->sweep_period_s();
  const double duration = o.frames * period + 1.0;
  const auto motion = *kind == sim::SceneKind::kLawn ? sim::follow_operator(scene, 1, duration)
                                                     : sim::drive_scene_route(scene, duration);
  sim::SimConfig cfg;
  cfg.range_noise_m = o.noise_m;
  cfg.dropout_probability = o.dropout;
  cfg.seed = o.seed + 1;
  const sim::LidarSimulator simulator(scene, *sensor, cfg);

  Trajectory poses;
  std::vector<double> frame_times;
  std::string people =
      "frame,stamp_s,id,x_m,y_m,vx_m_s,vy_m_s,heading_rad,leg0_x_m,leg0_y_m,leg1_x_m,leg1_y_m,"
      "points\n";
  std::size_t total_points = 0;
  const io::WriteOptions wo{.overwrite = o.force};
  // One PCD schema for every frame, as documented: `time` = s from the sweep start (frame 0 starts
  // at 0 s, the others would get absolute `timestamp`s); the sweep stamps are in times.txt.
  const io::WriteOptions pcd_wo{.overwrite = o.force, .time_offsets = true};
  ProgressLine progress;
  for (int i = 0; i < o.frames; ++i) {
    if (i % 10 == 0) progress.show("frame {} of {} ({:.0f} %)", i, o.frames, 100.0 * i / o.frames);
    const double t0 = i * period;
    const auto frame = simulator.scan(t0, motion.lidar_pose_fn());
    if (i == 0) {  // nothing is written before the run is known to fit
      check_disk_space(dir, frame.cloud.size(), o.frames);
      for (const char* sub : {"velodyne", "labels", "pcd"}) fs::create_directories(dir / sub);
    }
    const std::string name = fmt::format("{:06d}", i);
    io::write_kitti_bin(dir / "velodyne" / (name + ".bin"), frame.cloud, wo);
    io::write_labels(dir / "labels" / (name + ".label"), frame.cloud.labels, wo);
    io::write_cloud(dir / "pcd" / (name + ".pcd"), frame.cloud, pcd_wo);
    poses.push_back(t0, frame.T_world_lidar_start);
    frame_times.push_back(t0);
    total_points += frame.cloud.size();
    for (const auto& p : frame.people)
      people += fmt::format(
          "{},{:.4f},{},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{}\n", i, t0,
          p.id, p.position_m.x(), p.position_m.y(), p.velocity_m_s.x(), p.velocity_m_s.y(),
          p.heading_rad, p.legs_m[0].x(), p.legs_m[0].y(), p.legs_m[1].x(), p.legs_m[1].y(),
          p.points);
  }
  progress.end();
  io::write_kitti_poses(dir / "poses.txt", poses, wo);
  io::write_kitti_times(dir / "times.txt", poses, wo);
  io::write_tum(dir / "poses_tum.txt", poses, wo);
  const double t_last = (o.frames - 1) * period + period;
  write_text(
      dir / "imu.csv",
      imu_csv(sim::simulate_imu(motion.base_pose_fn(), 0.0, t_last, {.rate_hz = o.imu_rate_hz})),
      o.force);
  write_text(dir / "odom.csv",
             odom_csv(sim::simulate_wheel_odometry(motion.base_pose_fn(), 0.0, t_last,
                                                   {.rate_hz = o.odom_rate_hz})),
             o.force);
  if (!scene.walkers().empty()) write_text(dir / "people.csv", people, o.force);
  if (!scene.operator_path().empty()) {
    std::string s = "x_m,y_m\n";
    for (const auto& p : scene.operator_path()) s += fmt::format("{:.4f},{:.4f}\n", p.x(), p.y());
    write_text(dir / "operator_path.csv", s, o.force);
  }
  if (!scene.trunks().empty())
    write_text(dir / "trees.csv", truth_trees_csv(scene.trunks()), o.force);
  std::unique_ptr<Grid2D> terrain;
  if (*kind == sim::SceneKind::kTerrain) {
    terrain = std::make_unique<Grid2D>(scene.terrain_truth({.resolution_m = o.truth_resolution_m}));
    write_terrain_truth(dir, *terrain, o.force);
  }
  const Pose& Tbl = motion.T_base_lidar();
  nlohmann::json meta = {
      {"scene", o.scene},
      {"seed", o.seed},
      {"sensor", sensor->name},
      {"frames", o.frames},
      {"sweep_period_s", period},
      {"range_noise_m", simulator.config().range_noise_m},
      {"dropout_probability", o.dropout},
      {"T_base_lidar_xyz_m", {Tbl.translation().x(), Tbl.translation().y(), Tbl.translation().z()}},
      {"imu_rate_hz", o.imu_rate_hz},
      {"odom_rate_hz", o.odom_rate_hz},
      {"triangles", scene.mesh().size()},
      {"people", scene.walkers().size()},
      {"trees", scene.trunks().size()}};
  write_text(dir / "scene.json", meta.dump(2) + "\n", o.force);
  if (o.preview)
    write_preview(dir / "preview.png", scene, simulator, motion, frame_times, terrain.get(),
                  fmt::format("{} (seed {}), {} x {} frames; objects: plan section below 2.5 m",
                              o.scene, o.seed, sensor->name, o.frames),
                  o.force);
  const double secs =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  fmt::print("simulate: {} scene (seed {}), {} x {} frames, {:.0f} points/frame -> {} ({:.2f} s)\n",
             o.scene, o.seed, sensor->name, o.frames, double(total_points) / o.frames, dir.string(),
             secs);
}

}  // namespace

void add_simulate_command(CLI::App& app) {
  auto o = std::make_shared<SimulateOptions>();
  auto* cmd = app.add_subcommand(
      "simulate", "Simulate LiDAR frames with exact ground truth in a procedural scene");
  cmd->add_option("--scene", o->scene, "lawn, greenhouse, forest or terrain")->required();
  cmd->add_option(
         "--sensor", o->sensor,
         "Sensor preset (vlp16, vlp32c, hdl32e, hdl64e, os1-64, os1-128, os2-128, tilting2d)")
      ->capture_default_str();
  cmd->add_option("--frames", o->frames, "Number of sweeps")
      ->capture_default_str()
      ->check(whole_in(1, 100000));
  cmd->add_option("--seed", o->seed, "Scene and noise seed")
      ->capture_default_str()
      ->check(whole_in(0, kMaxSeed));
  cmd->add_option("--out", o->out, "Output folder")->required();
  cmd->add_flag("--preview", o->preview, "Also write preview.png (top-down scene with the truth)");
  cmd->add_flag("--force", o->force, "Replace existing output files");
  cmd->add_option("--noise", o->noise_m, "Range noise 1-sigma (m); default: the sensor's accuracy")
      ->check(real_in(0, 1));
  cmd->add_option("--dropout", o->dropout, "Random drop-out probability per return")
      ->capture_default_str()
      ->check(real_in(0, 1));
  cmd->add_option("--imu-rate", o->imu_rate_hz, "IMU rate (Hz)")
      ->capture_default_str()
      ->check(real_above(0, 10000));
  cmd->add_option("--odom-rate", o->odom_rate_hz, "Wheel odometry rate (Hz)")
      ->capture_default_str()
      ->check(real_above(0, 10000));
  cmd->add_option("--truth-resolution", o->truth_resolution_m, "Terrain truth cell size (m)")
      ->capture_default_str()
      ->check(real_in(0.05, 10));
  std::vector<CLI::Option*> lawn;  // the lawn scenario's options, refused with other scenes
  lawn.push_back(cmd->add_flag("--crossing", o->crossing,
                               "lawn: a second person crosses ahead of the operator"));
  lawn.push_back(
      cmd->add_flag("--operator-stops", o->stops, "lawn: the operator stands still for a while"));
  lawn.push_back(cmd->add_flag("--too-fast", o->too_fast,
                               "lawn: the operator walks faster than the mower can follow"));
  lawn.push_back(cmd->add_flag("--behind-shed", o->behind_shed,
                               "lawn: the operator's path passes behind the shed"));
  lawn.push_back(cmd->add_flag("--operator-waits", o->waits,
                               "lawn: the operator stands still for 5 s before walking off"));
  lawn.push_back(
      cmd->add_option("--rough", o->rough,
                      "lawn: amplitude of short bumps over the ground (tussocks and ruts, 2-4 m "
                      "wavelengths; m, 0: a mown lawn; 0.06 tilts the mower by up to ~8 deg)")
          ->capture_default_str()
          ->check(real_in(0, 0.3)));
  lawn.push_back(
      cmd->add_option("--extra-walkers", o->extra_walkers, "lawn: people strolling at random")
          ->capture_default_str()
          ->check(whole_in(0, 50)));
  lawn.push_back(
      cmd->add_option("--operator-speed", o->operator_speed, "lawn: operator walking speed (m/s)")
          ->capture_default_str()
          ->check(real_in(0.1, 3)));
  cmd->callback([o, lawn] {
    for (const auto* opt : lawn)
      if (opt->count() > 0 && o->scene != "lawn")
        throw Error(opt->get_name() + ": a lawn scenario setting; --scene " + o->scene +
                    " has no operator or lawn");
    run_simulate(*o);
  });
}

}  // namespace fieldlidar::app
