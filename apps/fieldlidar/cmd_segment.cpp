// fieldlidar segment INPUT: ground + clusters of one scan, as a label file, a labelled cloud and
// pictures (seeds 000 and 002, steps "remove the ground, cluster the rest").

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "fieldlidar/core/error.hpp"
#include "fieldlidar/core/sensor_model.hpp"
#include "fieldlidar/io/cloud_file.hpp"
#include "fieldlidar/io/label_file.hpp"
#include "fieldlidar/segmentation/ground.hpp"
#include "fieldlidar/segmentation/segment.hpp"
#include "support/canvas.hpp"
#include "support/option_checks.hpp"
#include "support/sensor_choice.hpp"
#include "support/warnings.hpp"

namespace fieldlidar::app {

namespace {
struct SegmentOptions {
  std::string input, method = "auto", sensor, clusters = "euclidean";
  std::vector<double> up;  ///< --up X,Y,Z: up in the lidar frame (empty: estimated)
  std::string labels_out, cloud_out, png_out;
  double tolerance_m = 0.5;
  std::size_t min_points = 21;
  bool force = false, json = false;
};

Rgb label_colour(std::uint32_t label) {
  using namespace segmentation;
  if (label == kLabelGround) return {0.55, 0.75, 0.45};
  if (label == kLabelUnclustered) return {0.6, 0.6, 0.6};
  if (label >= kLabelClusterBase) return palette(label - kLabelClusterBase + 1);
  return {1, 1, 1};
}

// `sensor` is null for a cloud that is not one sweep: the whole cloud is drawn, without a range
// image.
void draw_pictures(const std::string& path, const PointCloud& cloud, const SensorModel* sensor,
                   const std::vector<std::uint32_t>& labels, std::size_t clusters, bool force) {
  // Top-down view, +-40 m around the sensor at most.
  Bounds3 b = compute_bounds(cloud);
  if (b.empty()) throw Error("segment: " + path + ": the cloud has no valid point to draw");
  const double reach = sensor ? 40.0 : std::numeric_limits<double>::infinity();
  const Eigen::Vector2d lo(std::max(b.min.x(), -reach), std::max(b.min.y(), -reach));
  const Eigen::Vector2d hi(std::min(b.max.x(), reach), std::min(b.max.y(), reach));
  TopDownCanvas canvas(lo, hi, 1400);
  for (int pass = 0; pass < 2; ++pass)  // ground first, objects on top
    for (std::size_t i = 0; i < cloud.size(); ++i) {
      const bool ground = labels[i] == segmentation::kLabelGround;
      if (labels[i] == segmentation::kLabelInvalid || ground != (pass == 0)) continue;
      const auto& p = cloud.points[i];
      canvas.dot({p.x, p.y}, label_colour(labels[i]), ground ? 0.8 : 1.2);
    }
  canvas.title(fmt::format("{}: ground and {} clusters", path, clusters));
  canvas.legend({{"ground", label_colour(segmentation::kLabelGround)},
                 {"not in a cluster", label_colour(segmentation::kLabelUnclustered)},
                 {"clusters", palette(1)}});
  canvas.save_png(path, force);
  if (!sensor) return;
  // Range image view next to it: OUT.png -> OUT.range.png, rows = rings (top = highest beam).
  const segmentation::RangeImage image = segmentation::RangeImage::build(cloud, *sensor);
  RasterImage raster(image.cols, image.rows);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const std::int32_t cell = image.point_cell[i];
    if (cell < 0 || image.cell_point[cell] != std::int32_t(i)) continue;
    raster.set(image.col_of_cell(cell), image.rows - 1 - image.row_of_cell(cell),
               label_colour(labels[i]));
  }
  std::filesystem::path range_path(path);
  range_path.replace_extension(".range.png");
  const int sy = std::max(1, 256 / std::max(1, image.rows));
  raster.save_png(range_path, force, 1, sy);
}

// The ground method of --method; "auto" is robust for one sensor sweep, grid for any other cloud
// (said on stderr).
segmentation::GroundMethod choose_method(const SegmentOptions& o, const PointCloud& cloud) {
  if (o.method != "auto") return ground_method(o.method);
  const segmentation::SweepCheck check = segmentation::check_sweep(cloud);
  if (check.sweep || !o.sensor.empty()) return segmentation::GroundMethod::kRobust;
  fmt::print(stderr,
             "fieldlidar: warning: {}: not one sensor sweep ({}); ground by the grid method "
             "(give --method robust and --sensor for a sweep)\n",
             o.input, check.reason);
  return segmentation::GroundMethod::kGrid;
}

Eigen::Vector3d up_option(const std::vector<double>& up) {
  if (up.empty()) return Eigen::Vector3d::Zero();
  const Eigen::Vector3d v(up[0], up[1], up[2]);
  if (!v.allFinite() || !(v.norm() > 0))
    throw Error(
        fmt::format("--up {},{},{} is not a direction (finite, not zero)", up[0], up[1], up[2]));
  return v;
}

void run(const SegmentOptions& o) {
  // Refuse early, before the work: an output that exists without --force, that is not a regular
  // file, or that is the input itself.
  const std::vector<std::filesystem::path> inputs{o.input};
  std::filesystem::path range_png(o.png_out);
  range_png.replace_extension(".range.png");
  for (const auto& out : {o.labels_out, o.cloud_out, o.png_out, range_png.string()})
    if (!out.empty() && out != ".range.png") io::check_writable(out, o.force, inputs);
  const Eigen::Vector3d up = up_option(o.up);
  const PointCloud cloud = io::read_cloud(o.input);
  if (cloud.valid_count() == 0)
    throw Error(o.input + ": the scan has no valid point (" + std::to_string(cloud.size()) +
                " points): nothing to segment");
  if (const auto why = segmentation::implausible_span(cloud)) throw Error(o.input + ": " + *why);

  segmentation::SegmentConfig cfg;
  cfg.ground.method = choose_method(o, cloud);
  cfg.ground.levelling.up = up;
  const bool sweep = cfg.ground.method != segmentation::GroundMethod::kGrid;
  if (up.norm() > 0 && cfg.ground.method != segmentation::GroundMethod::kRobust)
    throw Error("segment: --up levels the robust ground only, not --method " +
                (sweep ? o.method : std::string("grid")));
  if (!sweep && o.clusters == "range-image")
    throw Error("segment: --clusters range-image needs one sensor sweep; " + o.input +
                " is not one: give --clusters euclidean");
  // The grid ground and the Euclidean clustering need no sensor.
  const SensorModel sensor = sweep ? sensor_for(cloud, o.input, o.sensor) : SensorModel::hdl64e();
  const std::string method_name = sweep ? (o.method == "auto" ? "robust" : o.method) : "grid";

  if (o.clusters == "euclidean")
    cfg.cluster_method = segmentation::ClusterMethod::kEuclidean;
  else if (o.clusters == "range-image")
    cfg.cluster_method = segmentation::ClusterMethod::kRangeImage;
  else
    throw Error("segment: --clusters '" + o.clusters + "' is not euclidean or range-image");
  cfg.euclidean.tolerance_m = o.tolerance_m;
  cfg.euclidean.min_points = o.min_points;
  const auto t0 = std::chrono::steady_clock::now();
  const segmentation::SegmentResult r = segmentation::segment(cloud, sensor, cfg);
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  const std::vector<std::uint32_t> labels = segmentation::segment_labels(cloud, r);

  io::WriteOptions w;
  w.overwrite = o.force;
  if (!o.labels_out.empty()) io::write_labels(o.labels_out, labels, w);
  if (!o.cloud_out.empty()) {
    PointCloud out = cloud;
    out.labels = labels;
    out.fields.label = true;
    io::write_cloud(o.cloud_out, out, w);
  }
  if (!o.png_out.empty())
    draw_pictures(o.png_out, cloud, sweep ? &sensor : nullptr, labels, r.clusters.clusters.size(),
                  o.force);

  nlohmann::json j;
  j["file"] = o.input;
  j["sensor"] = sweep ? nlohmann::json(sensor.name) : nlohmann::json(nullptr);
  j["method"] = method_name;
  j["points"] = cloud.size();
  j["valid_points"] = cloud.valid_count();
  j["ground_points"] = r.ground.ground_count;
  if (sweep) {
    j["sensor_height_m"] = r.ground.sensor_height_m;
    j["tilt_deg"] = r.ground.tilt_deg;
    j["levelled"] = r.ground.levelled;
    j["upside_down"] = r.ground.upside_down;
    j["ground_plane_found"] = r.ground.up_found;
  }
  j["clusters"] = r.clusters.clusters.size();
  j["time_ms"] = ms;
  if (sweep && !r.ground.up_found)
    warn(o.input +
         ": no ground plane below the sensor within 45 deg of its z axis, upright or "
         "turned over (a sensor tilted further?): segmented as if level; give --up");
  if (o.json) {
    std::printf("%s\n", j.dump(2).c_str());
    return;
  }
  fmt::print("file:          {}\n", o.input);
  if (sweep) {
    fmt::print("sensor:        {} (height above ground estimated {:.2f} m)\n", sensor.name,
               r.ground.sensor_height_m);
    fmt::print("tilt:          {:.1f} deg from {} ({})\n", r.ground.tilt_deg,
               up.norm() > 0 ? "--up" : "the ground plane",
               r.ground.upside_down ? "upside down: turned over before the ground"
               : r.ground.levelled  ? "levelled before the ground"
               : r.ground.up_found  ? "level enough, left as is"
                                    : "no ground plane found, taken as level");
  } else {
    fmt::print("sensor:        none (not one sweep)\n");
  }
  fmt::print("points:        {} ({} valid)\n", cloud.size(), cloud.valid_count());
  fmt::print("ground:        {} points ({})\n", r.ground.ground_count, method_name);
  fmt::print("clusters:      {} ({}, {:.2f} m, >= {} points)\n", r.clusters.clusters.size(),
             o.clusters, o.tolerance_m, o.min_points);
  fmt::print("time:          {:.1f} ms\n", ms);
}

}  // namespace

void add_segment_command(CLI::App& app) {
  auto opts = std::make_shared<SegmentOptions>();
  auto* cmd = app.add_subcommand(
      "segment", "Split one scan into ground and object clusters (label file, cloud, PNG)");
  cmd->add_option("INPUT", opts->input, "Input scan (.bin KITTI, .pcd, .ply, .las)")->required();
  cmd->add_option("--method", opts->method,
                  "Ground method: auto (robust for one sensor sweep, grid for any other cloud), "
                  "robust, grid, seed000, seed002")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "robust", "grid", "seed000", "seed002"}));
  cmd->add_option("--up", opts->up,
                  "Up direction X,Y,Z in the sensor frame, e.g. an IMU's accelerometer at rest "
                  "(robust ground; default: from the ground plane)")
      ->expected(3)
      ->delimiter(',');
  cmd->add_option("--sensor", opts->sensor,
                  "Sensor preset (vlp16, hdl32e, hdl64e, os1-64, ...); default from the rings");
  cmd->add_option("--clusters", opts->clusters, "Clustering: euclidean or range-image")
      ->capture_default_str()
      ->check(CLI::IsMember({"euclidean", "range-image"}));
  cmd->add_option("--tolerance", opts->tolerance_m, "Euclidean cluster distance (m)")
      ->capture_default_str()
      ->check(real_above(0, 100));
  cmd->add_option("--min-points", opts->min_points,
                  "Smallest cluster kept (seed 002 drops clusters of <= 20 points)")
      ->capture_default_str()
      ->check(whole_in(1, 100000000));
  cmd->add_option("--labels", opts->labels_out,
                  "Write a uint32 per point: 0 invalid, 1 ground, 2 other, 100+k cluster k");
  cmd->add_option("--out", opts->cloud_out, "Write the cloud with those labels (.pcd, .ply, ...)");
  cmd->add_option("--png", opts->png_out,
                  "Write a top-down PNG and, beside it as NAME.range.png, the range image");
  cmd->add_flag("-f,--force", opts->force, "Replace existing output files");
  cmd->add_flag("--json", opts->json, "Print machine-readable JSON");
  cmd->callback([opts] { run(*opts); });
}

}  // namespace fieldlidar::app
