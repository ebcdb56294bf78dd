// fieldlidar odometry: LiDAR odometry and mapping over any frame source (seed 002), with the IMU
// and wheel streams of a simulator folder or given files; poses, map and a picture of both.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/cloud_file.hpp"
#include "fieldlidar/io/file_util.hpp"
#include "fieldlidar/io/frame_source.hpp"
#include "fieldlidar/io/rosbag_reader.hpp"
#include "fieldlidar/io/trajectory_io.hpp"
#include "fieldlidar/odometry/lidar_odometry.hpp"
#include "support/canvas.hpp"
#include "support/motion_csv.hpp"
#include "support/option_checks.hpp"
#include "support/output_folder.hpp"
#include "support/progress_line.hpp"
#include "support/sensor_choice.hpp"
#include "support/warnings.hpp"

namespace fieldlidar::app {

namespace {

namespace fs = std::filesystem;

struct OdometryOptions {
  std::string input, imu, odom, map_in, out, sensor, topic, solver = "eigen_lm";
  std::vector<double> initial_pose;  ///< x y z roll pitch yaw (m, deg) in the map
  bool frame_to_frame = false, lidar_only = false, force = false;
  double elevation_correction_deg = 0.0;
};

/// A line "Name:  value kB" of /proc/self/status in MB (0 where there is none, e.g. not Linux).
double proc_status_mb(const std::string& name) {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(name + ":", 0) == 0) return std::atof(line.c_str() + name.size() + 1) / 1024.0;
  return 0.0;
}

/// Consecutive frames with a degenerate direction (an aisle, a wall): one warning per stretch.
struct DegenerateStretch {
  std::size_t first = 0, last = 0;
  double smallest = 0;
  bool open = false;
  void add(std::size_t frame, double ratio) {
    if (!open) first = frame, smallest = ratio, open = true;
    last = frame;
    smallest = std::min(smallest, ratio);
  }
  void flush() {
    if (!open) return;
    open = false;
    fmt::print(stderr, "\r");
    warn(
        fmt::format("frames {}-{}: degenerate geometry, a direction weakly constrained "
                    "(information ratio down to {:.3g})",
                    first, last, smallest));
  }
};

/// The lidar's mount on the base from a simulator folder's scene.json (identity without one).
Pose scene_base_lidar(const fs::path& folder) {
  Pose T = Pose::Identity();
  std::ifstream in(folder / "scene.json");
  if (!in) return T;
  const auto scene = nlohmann::json::parse(in, nullptr, false);
  if (scene.is_discarded() || !scene.contains("T_base_lidar_xyz_m")) return T;
  const auto& xyz = scene["T_base_lidar_xyz_m"];
  if (!xyz.is_array() || xyz.size() != 3)
    throw Error((folder / "scene.json").string() + ": T_base_lidar_xyz_m needs 3 numbers");
  T.translation() =
      Eigen::Vector3d(xyz[0].get<double>(), xyz[1].get<double>(), xyz[2].get<double>());
  return T;
}

/// --imu / --odom: a file, or a topic of the bag INPUT when no such file exists.
bool bag_topic(const std::string& value, const fs::path& input) {
  if (value.empty() || fs::exists(value)) return false;
  if (input.extension() == ".bag") return true;
  throw Error(value + ": no such file (a topic name needs a .bag INPUT)");
}

/// sensor_msgs/Imu messages of a bag topic (taken as the base frame: no extrinsics are read).
std::vector<ImuSample> read_imu_bag(const fs::path& bag, const std::string& topic) {
  return io::read_imu_topic(bag, topic);
}

/// Wheel speeds from nav_msgs/Odometry or geometry_msgs/TwistStamped of a bag topic: forward
/// speed = twist linear x, yaw rate = twist angular z (the base frame's twist).
std::vector<odometry::WheelSample> read_wheels_bag(const fs::path& bag, const std::string& topic) {
  std::vector<odometry::WheelSample> out;
  for (const auto& m : io::read_odometry_topic(bag, topic))
    out.push_back({m.stamp_s, m.linear_m_s.x(), m.angular_rad_s.z()});
  return out;
}

void draw_map(const fs::path& path, const PointCloud& map, const Trajectory& poses, bool force) {
  Bounds3 b = compute_bounds(map);
  for (const auto& p : poses) b.extend(p.pose.translation());
  if (b.empty()) return;
  TopDownCanvas canvas(b.min.head<2>(), b.max.head<2>(), 1400);
  for (const auto& p : map.points)
    canvas.dot({p.x, p.y}, p.intensity == 1.f ? Rgb{0.8, 0.3, 0.2} : Rgb{0.55, 0.6, 0.65}, 0.7);
  std::vector<Eigen::Vector2d> path_xy;
  for (const auto& p : poses) path_xy.push_back(p.pose.translation().head<2>());
  canvas.polyline(path_xy, {0.1, 0.2, 0.9}, 2.5);
  canvas.title(fmt::format("odometry: {} frames, {:.1f} m", poses.size(), poses.path_length_m()));
  canvas.legend(
      {{"edges", {0.8, 0.3, 0.2}}, {"planes", {0.55, 0.6, 0.65}}, {"path", {0.1, 0.2, 0.9}}});
  canvas.save_png(path, force);
}

void run_odometry(const OdometryOptions& o) {
  const fs::path out(o.out);
  const std::vector<std::string> names = {"poses.txt", "poses_tum.txt", "map.pcd", "map.png",
                                          "summary.json"};
  const OutputFolder folder(out);  // gone again if the input is refused before any output
  for (const auto& n : names) io::check_writable(out / n, o.force);

  // A simulator folder: its IMU and wheel streams beside its frames (FrameSource::open reads
  // its pcd/, stamped by its times.txt).
  const fs::path input(o.input);
  fs::path imu_path(o.imu), odom_path(o.odom);
  odometry::OdometryConfig cfg;
  if (fs::is_directory(input) && fs::exists(input / "imu.csv")) {
    if (imu_path.empty()) imu_path = input / "imu.csv";
    if (odom_path.empty() && fs::exists(input / "odom.csv")) odom_path = input / "odom.csv";
    cfg.deskew.T_base_lidar = scene_base_lidar(input);
  }
  if (o.lidar_only) imu_path.clear(), odom_path.clear();
  const bool imu_topic = bag_topic(imu_path.string(), input);
  const bool odom_topic = bag_topic(odom_path.string(), input);
  std::vector<odometry::ImuSample> imu;
  std::vector<odometry::WheelSample> wheels;
  if (!imu_path.empty()) imu = imu_topic ? read_imu_bag(input, o.imu) : read_imu_csv(imu_path);
  if (!odom_path.empty())
    wheels = odom_topic ? read_wheels_bag(input, o.odom) : read_wheels_csv(odom_path);
  // The map to localise in, read before any frame: a map with nothing to match is refused here
  // rather than leaving every frame unregistered.
  PointCloud map_in;
  if (!o.map_in.empty()) {
    map_in = io::read_cloud(o.map_in);
    if (map_in.valid_count() == 0) throw Error("--map-in " + o.map_in + ": the map has no points");
  }
  io::SourceOptions so;
  so.topic = o.topic;
  auto source = io::FrameSource::open(input, so);
  if (o.frame_to_frame) cfg.target = odometry::MatchTarget::kPreviousFrame;
  cfg.preprocess.elevation_correction_deg = o.elevation_correction_deg;
  cfg.lm.solver = odometry::parse_lm_solver(o.solver);
  if (cfg.lm.solver == odometry::LmSolver::kCeres && !odometry::ceres_available())
    throw Error("--solver ceres: this fieldlidar was built without Ceres (libceres-dev)");
  nlohmann::json memory = nlohmann::json::array();
  std::unique_ptr<odometry::LidarOdometry> odo;
  Trajectory poses;
  std::size_t degenerate = 0, unregistered = 0, registered = 0, warnings = 0, points = 0;
  std::vector<double> frame_ms;
  DegenerateStretch stretch;
  double last_stamp = -1e300;
  const auto t_start = std::chrono::steady_clock::now();
  ProgressLine progress;
  while (auto frame = source->next()) {
    PointCloud& cloud = frame->cloud;
    points += cloud.size();
    if (!odo) {
      const SensorModel sensor =
          source->sensor() ? *source->sensor() : sensor_for(cloud, o.input, o.sensor);
      cfg.expected_period_s = sensor.sweep_period_s();
      odo = std::make_unique<odometry::LidarOdometry>(sensor, cfg);
      if (!imu.empty()) odo->add_imu(imu);
      if (!wheels.empty()) odo->add_wheels(wheels);
      if (!o.map_in.empty()) {
        Pose start = Pose::Identity();
        if (o.initial_pose.size() == 6) {
          const double d = M_PI / 180;
          const auto& v = o.initial_pose;
          start = make_pose(v[0], v[1], v[2], v[3] * d, v[4] * d, v[5] * d);
        }
        odo->set_map(odometry::LocalMap::from_cloud(map_in, cfg.map), start);
      }
    }
    // Files without stamps: one sweep period apart.
    if (cloud.stamp_s <= 0 && frame->index > 0)
      cloud.stamp_s = frame->index * cfg.expected_period_s;
    const auto r = odo->register_frame(cloud);
    if (!r.warnings.empty()) progress.interrupt();  // over the progress line
    for (const auto& w : r.warnings) warn(fmt::format("frame {}: {}", frame->index, w));
    warnings += r.warnings.size();
    degenerate += r.degenerate;
    unregistered += !r.registered && frame->index > 0;
    registered += r.registered;
    if (r.degenerate)
      stretch.add(frame->index, r.information_ratio.minCoeff());
    else
      stretch.flush();
    frame_ms.push_back(r.timings.total_ms);
    const double stamp = cloud.stamp_s > last_stamp ? cloud.stamp_s : last_stamp + 1e-6;
    last_stamp = stamp;
    poses.push_back(stamp, r.T_world_lidar);
    if (poses.size() % 1000 == 0)
      memory.push_back({{"frames", poses.size()},
                        {"rss_mb", proc_status_mb("VmRSS")},
                        {"map_points", odo->map().size()}});
    progress.show("frame {} ({:.0f} %): {:.1f} ms, {} matches   ", frame->index,
                  100 * source->progress(), r.timings.total_ms, r.inliers);
  }
  stretch.flush();
  progress.end();
  warn_source_losses(*source);
  if (!odo) throw Error(o.input + ": no frame");
  if (points == 0) throw Error(o.input + ": holds no points: nothing to register");
  // Localisation that never matched the map: the poses are the prior alone (the initial pose
  // carried on by IMU, wheels or nothing), not positions in the map.
  if (!o.map_in.empty() && registered == 0)
    throw Error(fmt::format(
        "--map-in {}: none of the {} frames registered in the map (too few feature matches); "
        "is the map of this place, and --initial-pose near the first frame's pose in it?",
        o.map_in, poses.size()));

  const io::WriteOptions wo{.overwrite = o.force};
  io::write_kitti_poses(out / "poses.txt", poses, wo);
  io::write_tum(out / "poses_tum.txt", poses, wo);
  const PointCloud map = odo->map_cloud();
  io::write_cloud(out / "map.pcd", map, wo);
  draw_map(out / "map.png", map, poses, o.force);
  std::vector<double> sorted = frame_ms;
  std::sort(sorted.begin(), sorted.end());
  const double median = sorted[sorted.size() / 2];
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  const nlohmann::json summary = {{"input", o.input},
                                  {"frames", poses.size()},
                                  {"path_length_m", poses.path_length_m()},
                                  {"median_ms_per_frame", median},
                                  {"degenerate_frames", degenerate},
                                  {"unregistered_frames", unregistered},
                                  {"warnings", warnings},
                                  {"map_points", map.size()},
                                  {"memory_per_1000_frames", memory},
                                  {"peak_rss_mb", proc_status_mb("VmHWM")},
                                  {"imu", imu_path.string()},
                                  {"imu_samples", imu.size()},
                                  {"wheels", odom_path.string()},
                                  {"wheel_samples", wheels.size()},
                                  {"map_in", o.map_in},
                                  {"solver", odometry::lm_solver_name(cfg.lm.solver)},
                                  {"seconds", seconds}};
  const std::string text = summary.dump(2) + "\n";
  io::write_file_atomic(out / "summary.json", text.data(), text.size(), o.force);
  fmt::print("odometry: {} frames, {:.2f} m, median {:.1f} ms per frame, {} degenerate -> {}\n",
             poses.size(), poses.path_length_m(), median, degenerate, out.string());
}

}  // namespace

void add_odometry_command(CLI::App& app) {
  auto o = std::make_shared<OdometryOptions>();
  auto* cmd = app.add_subcommand("odometry", "LiDAR odometry and mapping (seed 002)");
  cmd->add_option("input", o->input, "Frames: a file, folder, glob, pcap, bag or simulator folder")
      ->required();
  cmd->add_option("--topic", o->topic, "Bag topic of the frames (default: the only scan topic)");
  cmd->add_option("--imu", o->imu,
                  "IMU CSV (stamp_s, gyro xyz rad/s, accel xyz m/s^2), or a sensor_msgs/Imu topic "
                  "of the bag INPUT");
  cmd->add_option(
      "--odom", o->odom,
      "Wheel CSV (simulator odom.csv or stamp,linear,yaw_rate), or a nav_msgs/Odometry "
      "or geometry_msgs/TwistStamped topic of the bag INPUT (twist linear x, angular z)");
  cmd->add_option("--map-in", o->map_in, "Localise in this saved map (map.pcd of an earlier run)");
  cmd->add_option("--initial-pose", o->initial_pose, "x y z roll pitch yaw (m, deg) in --map-in")
      ->expected(6)
      ->check(real_finite());
  cmd->add_option("--sensor", o->sensor, "Sensor preset when the input does not say");
  cmd->add_flag("--frame-to-frame", o->frame_to_frame, "Seed 002 matching against the last frame");
  cmd->add_option("--elevation-correction", o->elevation_correction_deg,
                  "Added to every point's elevation (deg): 0.22 for KITTI's HDL-64E clouds")
      ->check(real_in(-2, 2));
  cmd->add_option("--solver", o->solver,
                  "Levenberg-Marquardt of the matching: eigen_lm (default) or ceres (same "
                  "problem, when built with libceres-dev)")
      ->check(CLI::IsMember({"eigen_lm", "ceres"}));
  cmd->add_flag("--lidar-only", o->lidar_only,
                "Ignore IMU and wheels (also those of a simulator folder)");
  cmd->add_option("-o,--out", o->out, "Output folder")->required();
  cmd->add_flag("-f,--force", o->force, "Replace existing output files");
  cmd->callback([o] { run_odometry(*o); });
}

}  // namespace fieldlidar::app
