// fieldlidar trunks INPUT --out DIR: tree trunks of one scan or plot file (seed 003, steps 1-3):
// trees.csv, trees.geojson and a top-down picture of the stems as DBH circles over the points;
// of a sequence: the pose of every scan tracked against a trunk map, and that map.

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/core.h>

#include "commands.hpp"
#include "fieldlidar/core/error.hpp"
#include "fieldlidar/core/rotate_points.hpp"
#include "fieldlidar/forest/stem_slice.hpp"
#include "fieldlidar/forest/tracking.hpp"
#include "fieldlidar/forest/trunks.hpp"
#include "fieldlidar/io/cloud_file.hpp"
#include "fieldlidar/io/file_util.hpp"
#include "fieldlidar/io/frame_source.hpp"
#include "fieldlidar/io/trajectory_io.hpp"
#include "fieldlidar/odometry/lidar_odometry.hpp"
#include "fieldlidar/segmentation/ground.hpp"
#include "support/option_checks.hpp"
#include "support/output_folder.hpp"
#include "support/progress_line.hpp"
#include "support/sensor_choice.hpp"
#include "support/sweep_levelling.hpp"
#include "support/trunks_output.hpp"
#include "support/trunks_truth.hpp"
#include "support/warnings.hpp"

namespace fieldlidar::app {
namespace {

namespace fs = std::filesystem;

struct TrunksOptions {
  std::string input, out, sensor, truth;
  double max_radius_m = 0.6;
  double slice_m = 0.15;
  bool force = false;
  bool odometry = false;
};

bool is_sequence(const fs::path& input) {
  if (fs::is_directory(input)) return true;
  const std::string ext = io::extension_of(input);
  return input.string().find('*') != std::string::npos || ext == "pcap" || ext == "bag" ||
         ext == "db3" || ext == "mcap";
}

/// --truth's trees (world frame), read before anything is written; none without --truth.
using Truth = std::optional<std::vector<TrueTree>>;

/// The move of --truth's trees into the frame of a cloud's points: a simulator scan's pose
/// (`T_world_scan`), then the cloud's own recentring (a plot file's origin_m).
Pose truth_to_cloud(const PointCloud& cloud, const std::optional<Pose>& T_world_scan) {
  Pose T_cloud_world = T_world_scan ? T_world_scan->inverse() : Pose::Identity();
  T_cloud_world.pretranslate(-cloud.origin_m);
  return T_cloud_world;
}

// A sequence: every scan tracked against the trunk map (optionally on the odometry's motion).
void run_sequence(const TrunksOptions& o, const Truth& truth) {
  const fs::path out(o.out);
  const OutputFolder folder(out);  // gone again if the input is refused before any output
  for (const char* n : {"poses.txt", "poses_tum.txt", "trees.csv", "trees.geojson", "trees.png"})
    io::check_writable(out / n, o.force, {fs::path(o.input)});
  const fs::path input(o.input);
  Pose T_world_first = Pose::Identity();
  bool have_first = false;
  if (fs::is_directory(input) && fs::is_directory(input / "pcd") &&
      fs::exists(input / "poses.txt")) {  // a simulator folder
    const auto ref = io::read_kitti_poses(input / "poses.txt");
    if (!ref.empty()) T_world_first = ref[0].pose, have_first = true;
  }
  auto source = io::FrameSource::open(input);
  std::unique_ptr<forest::TrunkTracker> tracker;
  std::optional<odometry::LidarOdometry> odo;
  std::optional<SensorModel> sensor;
  Trajectory poses;
  std::vector<Eigen::Vector3d> path;
  Pose odo_prev = Pose::Identity();
  std::size_t tracked = 0, points = 0;
  ProgressLine progress;
  // A sensor mounted tilted or upside down: every scan is laid level by the rotation that levels
  // the first (the mount's; said once), so the trunks stand upright in the map and its poses.
  std::optional<Pose> T_level;
  while (auto frame = source->next()) {
    PointCloud& cloud = frame->cloud;
    points += cloud.valid_count();
    if (const auto why = segmentation::implausible_span(cloud))
      throw Error(fmt::format("{}: frame {}: {}", o.input, frame->index, *why));
    if (!cloud.fields.ring)
      throw Error(
          fmt::format("{}: frame {} has no ring field; tracking needs the scan lines of a "
                      "spinning sensor",
                      o.input, frame->index));
    if (!T_level) T_level = levelling_pose(cloud, {}, o.input);
    rotate_points(cloud, T_level->linear().cast<float>());
    if (!sensor) {
      sensor = source->sensor() ? *source->sensor() : sensor_for(cloud, o.input, o.sensor);
      forest::TrackerConfig cfg;
      cfg.sweep_period_s = sensor->sweep_period_s();
      tracker = std::make_unique<forest::TrunkTracker>(cfg);
      if (o.odometry) odo.emplace(*sensor);
    }
    if (cloud.stamp_s <= 0 && frame->index > 0)
      cloud.stamp_s = frame->index * sensor->sweep_period_s();
    const auto ground = segmentation::segment_ground(cloud, *sensor);
    std::optional<Pose> prior;
    if (odo) {
      const Pose p = odo->register_frame(cloud).T_world_lidar;
      if (!poses.empty()) prior = odo_prev.inverse() * p;
      odo_prev = p;
    }
    const auto r = tracker->track(cloud, ground.is_ground, prior);
    tracked += r.tracked;
    const double stamp = poses.empty() || cloud.stamp_s > poses.poses().back().stamp_s
                             ? cloud.stamp_s
                             : poses.poses().back().stamp_s + 1e-6;
    poses.push_back(stamp, r.T_world_lidar);
    path.push_back(r.T_world_lidar.translation());
    progress.show("frame {} ({:.0f} %): {} trees, {} matched   ", frame->index,
                  100 * source->progress(), r.trees, r.matched);
  }
  progress.end();
  warn_source_losses(*source);
  if (!tracker) throw Error(o.input + ": no frame");
  if (points == 0) throw Error(o.input + ": holds no points: no trunks to look for");
  const auto trees = tracker->map_trees();
  const io::WriteOptions wo{.overwrite = o.force};
  io::write_kitti_poses(out / "poses.txt", poses, wo);
  io::write_tum(out / "poses_tum.txt", poses, wo);
  io::write_file_atomic(out / "trees.csv", trees_csv(trees, Eigen::Vector3d::Zero()), o.force);
  io::write_file_atomic(out / "trees.geojson", trees_geojson(trees, Eigen::Vector3d::Zero()),
                        o.force);
  draw_trunk_map(trees, path, out / "trees.png", o.force);
  fmt::print(
      "{}: {} scans ({} tracked on trunks{}), {:.2f} m; trunk map: {} trees seen in 5 scans or "
      "more -> {}\n",
      o.input, poses.size(), tracked, odo ? ", odometry prior" : "", poses.path_length_m(),
      trees.size(), out.string());
  if (truth) {
    if (!have_first)
      warn(
          "--truth: no simulator poses.txt next to the frames; the truth is taken in the frame "
          "of the first scan");
    print_trunk_scores(
        trees, moved(*truth, T_level.value_or(Pose::Identity()) * T_world_first.inverse()), path);
  }
}

// A stem slice (a cloud under 0.5 m thick, cut at breast height from one stem or a whole plot):
// each stem's circle, the diameter at the slice's height. No ground: z_base_m is the lowest
// point of the stem's cluster.
void run_slice(const TrunksOptions& o, const PointCloud& cloud, const Truth& truth) {
  const fs::path out(o.out);
  forest::StemSliceConfig sc;
  sc.max_radius_m = o.max_radius_m;
  const auto stems = forest::measure_slice_stems(cloud, sc);
  std::vector<forest::Tree> trees;
  for (const auto& s : stems) {
    forest::Tree t;
    t.id = std::uint32_t(trees.size() + 1);
    t.base_m = {s.circle.center.x(), s.circle.center.y(), s.z_min_m};
    t.dbh_m = 2 * s.circle.radius_m;
    t.z_max_seen_m = s.z_max_m - s.z_min_m;
    t.arc_deg = s.arc_deg;
    t.residual_m = s.circle.residual_m;
    t.observations = 1;
    trees.push_back(t);
  }
  io::write_file_atomic(out / "trees.csv", trees_csv(trees, cloud.origin_m), o.force);
  io::write_file_atomic(out / "trees.geojson", trees_geojson(trees, cloud.origin_m), o.force);
  draw_slice(cloud, trees, out / "trees.png", o.force);
  fmt::print(
      "{}: a stem slice ({} points, {:.2f} m thick): {} stems, each a circle holding {} points "
      "within {:.3f} m over {:.0f} deg or more; branches and other points left out -> {}\n",
      o.input, cloud.valid_count(), forest::slice_thickness_m(cloud), trees.size(), sc.min_points,
      sc.inlier_band_m, sc.min_arc_deg, out.string());
  for (std::size_t k = 0; k < trees.size(); ++k) {
    const Eigen::Vector3d c = trees[k].base_m + cloud.origin_m;
    fmt::print(
        "  stem {} at ({:.3f}, {:.3f}): diameter {:.3f} m ({} points on the circle, arc "
        "{:.0f} deg, residual {:.4f} m)\n",
        trees[k].id, c.x(), c.y(), trees[k].dbh_m, stems[k].inliers, stems[k].arc_deg,
        stems[k].circle.residual_m);
  }
  if (truth) print_trunk_scores(trees, moved(*truth, truth_to_cloud(cloud, std::nullopt)), {});
}

void run(const TrunksOptions& o) {
  // A missing or broken truth fails the run before any output is written, whatever the input.
  Truth truth;
  if (!o.truth.empty()) truth = read_true_trees(o.truth);
  if (is_sequence(o.input)) return run_sequence(o, truth);
  const fs::path out(o.out);
  const std::vector<std::string> names = {"trees.csv", "trees.geojson", "trees.png"};
  const OutputFolder folder(out);
  for (const auto& n : names) io::check_writable(out / n, o.force, {fs::path(o.input)});
  PointCloud cloud = io::read_cloud(o.input);
  if (cloud.valid_count() == 0) throw Error(o.input + ": holds no points: no trunks to look for");
  if (const auto why = segmentation::implausible_span(cloud)) throw Error(o.input + ": " + *why);
  if (!cloud.fields.ring && forest::is_stem_slice(cloud)) return run_slice(o, cloud, truth);
  // A sweep from a sensor mounted tilted or upside down is levelled first (its trunks stand up);
  // the trees are given in that levelled frame.
  const bool sweep = segmentation::check_sweep(cloud).sweep;
  const Pose level = sweep ? levelling_pose(cloud, {}, o.input) : Pose::Identity();
  rotate_points(cloud, level.linear().cast<float>());
  // A sweep with rings gets the robust ground; a plot file, or a sweep without rings (its trunks
  // come from horizontal slices, as a plot's do), the grid: the ring-less sweep of forest_sloam
  // gave no stack at all on the robust ground.
  segmentation::GroundResult ground;
  if (sweep && cloud.fields.ring) {
    ground = segmentation::segment_ground(cloud, sensor_for(cloud, o.input, o.sensor));
  } else {
    ground = segmentation::ground_grid(cloud);
  }
  forest::TreeConfig cfg;
  cfg.max_radius_m = o.max_radius_m;
  cfg.segments.max_radius_m = o.max_radius_m;
  cfg.segments.slice_m = o.slice_m;
  // A plot file (not one sensor-centred sweep) is taken as seen from all round: its stems must
  // reach down to breast height and fill their slices.
  cfg.plot_full_view = !sweep && !cloud.fields.ring;
  const auto result = forest::extract_trees(cloud, ground.is_ground, cfg);
  io::write_file_atomic(out / "trees.csv", trees_csv(result.trees, cloud.origin_m), o.force);
  io::write_file_atomic(out / "trees.geojson", trees_geojson(result.trees, cloud.origin_m),
                        o.force);
  draw_trees(cloud, ground.is_ground, result.trees, out / "trees.png", o.force);
  fmt::print("{}: {} points ({}), {} ground; {} scan segments, {} stacks, {} trees -> {}\n",
             o.input, cloud.size(),
             fmt::format("{}, {}", sweep ? "sweep" : "plot",
                         cloud.fields.ring ? "rings" : "horizontal slices"),
             ground.ground_count, result.segments, result.stacks, result.trees.size(),
             out.string());
  if (truth) {
    // A simulator scan lies in its sensor's frame: the truth is moved into it from the world
    // with the scan's pose, and scored within the 15 m of the sensor.
    const auto T_world_scan = simulator_scan_pose(o.input);
    if (sweep && !T_world_scan)
      warn("--truth: no simulator poses.txt for this scan; the truth is taken in its frame");
    const auto in_cloud = moved(*truth, level * truth_to_cloud(cloud, T_world_scan));
    if (sweep)
      print_trunk_scores(result.trees, in_cloud, {Eigen::Vector3d::Zero()}, 15.0);
    else
      print_trunk_scores(result.trees, in_cloud, {});
  }
}

}  // namespace

void add_trunks_command(CLI::App& app) {
  auto o = std::make_shared<TrunksOptions>();
  auto* cmd = app.add_subcommand(
      "trunks", "Tree trunks of one scan or plot file: positions, DBH at 1.3 m, quality");
  cmd->add_option("INPUT", o->input,
                  "Scan or plot file (.pcd, .las, .ply, .bin), or a sequence (folder, glob, "
                  "pcap, bag, simulator folder)")
      ->required();
  cmd->add_option("--out", o->out,
                  "Output folder (trees.csv, trees.geojson, trees.png; poses.txt and "
                  "poses_tum.txt for a sequence)")
      ->required();
  cmd->add_option("--truth", o->truth,
                  "Simulator trees.csv (or one in the input's own coordinates): print precision, "
                  "recall, DBH RMSE/bias, position RMSE; read and checked before anything is "
                  "written");
  cmd->add_flag("--odometry", o->odometry,
                "Sequence: the seed 002 odometry gives each scan's prior motion");
  cmd->add_option("--sensor", o->sensor, "Sensor preset for a sweep; default from the rings")
      ->check(sensor_preset());
  cmd->add_option("--max-radius", o->max_radius_m, "Largest stem radius U (m)")
      ->check(real_in(0.05, 3.0))
      ->capture_default_str();
  cmd->add_option("--slice", o->slice_m, "Slice thickness for clouds without rings (m)")
      ->check(real_in(0.02, 1.0))
      ->capture_default_str();
  cmd->add_flag("-f,--force", o->force, "Replace existing output files");
  cmd->callback([o] { run(*o); });
}

}  // namespace fieldlidar::app
