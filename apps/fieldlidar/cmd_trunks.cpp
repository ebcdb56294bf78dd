// fieldlidar trunks INPUT --out DIR: tree trunks of one scan or plot file (seed 003, steps 1-3):
// trees.csv, trees.geojson and a top-down picture of the stems as DBH circles over the points;
// of a sequence: the pose of every scan tracked against a trunk map, and that map.

#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <string>
#include <unordered_map>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "fieldlidar/core/error.hpp"
#include "fieldlidar/forest/tracking.hpp"
#include "fieldlidar/forest/trunks.hpp"
#include "fieldlidar/io/cloud_file.hpp"
#include "fieldlidar/io/file_util.hpp"
#include "fieldlidar/io/frame_source.hpp"
#include "fieldlidar/io/trajectory_io.hpp"
#include "fieldlidar/odometry/lidar_odometry.hpp"
#include "fieldlidar/segmentation/ground.hpp"
#include "support/canvas.hpp"
#include "support/option_checks.hpp"
#include "support/sensor_choice.hpp"
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

// A true tree of the simulator's trees.csv: axis point at 1.3 m and DBH.
struct TrueTree {
  Eigen::Vector3d at_dbh;
  double dbh_m;
};

std::vector<TrueTree> read_truth(const fs::path& path, const Pose& T_frame_world) {
  const auto bytes = io::read_file_bytes(path);
  const std::string text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  std::vector<TrueTree> out;
  std::size_t pos = text.find('\n'), line = 1;
  while (pos != std::string::npos && pos + 1 < text.size()) {
    const std::size_t end = text.find('\n', pos + 1);
    const std::string row = text.substr(pos + 1, end - pos - 1);
    pos = end;
    ++line;
    if (row.empty()) continue;
    std::vector<double> v;
    std::size_t a = 0;
    try {
      while (a <= row.size() && v.size() < 8) {
        const std::size_t b = row.find(',', a);
        v.push_back(std::stod(row.substr(a, b - a)));
        if (b == std::string::npos) break;
        a = b + 1;
      }
    } catch (const std::exception&) {
      throw Error(fmt::format("{}: line {}: not a number", path.string(), line));
    }
    if (v.size() < 8)
      throw Error(
          fmt::format("{}: line {}: expected id,base_x_m,base_y_m,base_z_m,axis_x,axis_y,"
                      "axis_z,dbh_m,...",
                      path.string(), line));
    const Eigen::Vector3d base(v[1], v[2], v[3]), axis = Eigen::Vector3d(v[4], v[5], v[6]);
    if (!(axis.z() > 0.1)) throw Error(fmt::format("{}: line {}: axis_z", path.string(), line));
    out.push_back(
        {T_frame_world * (base + axis.normalized() * (1.3 / axis.normalized().z())), v[7]});
  }
  return out;
}

// Detection scores of `trees` against the truth; with a path, only trees within 10 m of it count
// (and detections farther than 10.5 m are not scored). A match lies within 0.3 m at 1.3 m.
void print_scores(const std::vector<forest::Tree>& trees, const std::vector<TrueTree>& truth,
                  const std::vector<Eigen::Vector3d>& path) {
  auto near_path = [&](const Eigen::Vector3d& p, double r) {
    if (path.empty()) return true;
    for (const auto& q : path)
      if ((q - p).head<2>().norm() <= r) return true;
    return false;
  };
  std::vector<char> used(truth.size(), 0);
  int scored = 0, detected = 0, matched = 0, uncertain = 0;
  double dbh_sq = 0, dbh_sum = 0, pos_sq = 0;
  for (const auto& t : truth) scored += near_path(t.at_dbh, 10.0);
  for (const auto& d : trees) {
    const Eigen::Vector3d p = d.at_height(1.3);
    if (!near_path(p, 10.5)) continue;
    std::size_t best = truth.size();
    double bd = 0.3;
    for (std::size_t k = 0; k < truth.size(); ++k)
      if (!used[k] && (truth[k].at_dbh - p).head<2>().norm() < bd) {
        bd = (truth[k].at_dbh - p).head<2>().norm();
        best = k;
      }
    if (best < truth.size() && !near_path(truth[best].at_dbh, 10.0)) {
      used[best] = 1;
      continue;
    }
    ++detected;
    if (best == truth.size()) continue;
    used[best] = 1;
    ++matched;
    pos_sq += bd * bd;
    if (d.dbh_uncertain) {
      ++uncertain;
      continue;
    }
    dbh_sq += std::pow(d.dbh_m - truth[best].dbh_m, 2);
    dbh_sum += d.dbh_m - truth[best].dbh_m;
  }
  const double m = std::max(matched, 1), md = std::max(matched - uncertain, 1);
  fmt::print(
      "truth: {} trees{}, {} detected, {} matched: precision {:.3f}, recall {:.3f}, DBH RMSE "
      "{:.4f} m, bias {:+.4f} m (over {} with a measured DBH; {} marked uncertain), position "
      "RMSE {:.4f} m\n",
      scored, path.empty() ? "" : " within 10 m of the path", detected, matched,
      detected ? double(matched) / detected : 1.0, scored ? double(matched) / scored : 1.0,
      std::sqrt(dbh_sq / md), dbh_sum / md, matched - uncertain, uncertain, std::sqrt(pos_sq / m));
}

std::string trees_csv(const std::vector<forest::Tree>& trees, const Eigen::Vector3d& origin) {
  std::string s =
      "id,x_m,y_m,z_base_m,dbh_m,axis_x,axis_y,axis_z,height_seen_m,arc_deg,"
      "residual_m,observations,dbh_uncertain\n";
  for (const auto& t : trees) {
    const Eigen::Vector3d b = t.base_m + origin;
    s += fmt::format(
        "{},{:.3f},{:.3f},{:.3f},{:.4f},{:.4f},{:.4f},{:.4f},{:.2f},{:.1f},{:.4f},{},{}\n", t.id,
        b.x(), b.y(), b.z(), t.dbh_m, t.axis.x(), t.axis.y(), t.axis.z(),
        t.z_max_seen_m - t.z_min_seen_m, t.arc_deg, t.residual_m, t.observations,
        int(t.dbh_uncertain));
  }
  return s;
}

std::string trees_geojson(const std::vector<forest::Tree>& trees, const Eigen::Vector3d& origin) {
  nlohmann::json fc = {{"type", "FeatureCollection"}, {"features", nlohmann::json::array()}};
  for (const auto& t : trees) {
    const Eigen::Vector3d b = t.base_m + origin;
    fc["features"].push_back(
        {{"type", "Feature"},
         {"geometry", {{"type", "Point"}, {"coordinates", {b.x(), b.y(), b.z()}}}},
         {"properties",
          {{"id", t.id},
           {"dbh_m", t.dbh_m},
           {"height_seen_m", t.z_max_seen_m - t.z_min_seen_m},
           {"arc_deg", t.arc_deg},
           {"residual_m", t.residual_m},
           {"observations", t.observations},
           {"ground_found", t.ground_found},
           {"dbh_uncertain", t.dbh_uncertain}}}});
  }
  return fc.dump(1) + "\n";
}

// Height of each point above the ground: the lowest ground return of its 1 m cell (or of the
// nearest cells around it); NaN where no ground is near.
std::vector<float> height_above_ground(const PointCloud& cloud,
                                       const std::vector<std::uint8_t>& ground) {
  std::unordered_map<std::int64_t, float> low;
  auto key = [](float x, float y) {
    return (std::int64_t(std::floor(x)) << 32) ^ (std::int64_t(std::floor(y)) & 0xffffffff);
  };
  for (std::size_t i = 0; i < cloud.size(); ++i)
    if (ground[i] && cloud.points[i].is_valid()) {
      auto [it, fresh] = low.emplace(key(cloud.points[i].x, cloud.points[i].y), cloud.points[i].z);
      if (!fresh) it->second = std::min(it->second, cloud.points[i].z);
    }
  std::vector<float> h(cloud.size(), std::numeric_limits<float>::quiet_NaN());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const auto& p = cloud.points[i];
    if (!p.is_valid()) continue;
    for (int r = 0; r <= 2 && std::isnan(h[i]); ++r)
      for (int dx = -r; dx <= r; ++dx)
        for (int dy = -r; dy <= r; ++dy) {
          auto it = low.find(key(p.x + float(dx), p.y + float(dy)));
          if (it != low.end() && (std::isnan(h[i]) || p.z - it->second < h[i]))
            h[i] = p.z - it->second;
        }
  }
  return h;
}

// Top-down: every point faint, the 1.2-1.4 m slice above the ground dark, the DBH circles.
void draw(const PointCloud& cloud, const std::vector<std::uint8_t>& ground,
          const std::vector<forest::Tree>& trees, const fs::path& path, bool force) {
  const Bounds3 b = compute_bounds(cloud);
  if (b.empty()) return;
  TopDownCanvas canvas(b.min.head<2>(), b.max.head<2>());
  const auto h = height_above_ground(cloud, ground);
  const std::size_t step = std::max<std::size_t>(1, cloud.size() / 200000);
  for (std::size_t i = 0; i < cloud.size(); i += step)
    if (cloud.points[i].is_valid() && !(h[i] >= 1.2f && h[i] <= 1.4f))
      canvas.dot({cloud.points[i].x, cloud.points[i].y},
                 ground[i] ? Rgb{0.9, 0.87, 0.8} : Rgb{0.85, 0.87, 0.9}, 0.5);
  for (std::size_t i = 0; i < cloud.size(); ++i)
    if (h[i] >= 1.2f && h[i] <= 1.4f)
      canvas.dot({cloud.points[i].x, cloud.points[i].y}, {0.15, 0.15, 0.2}, 0.7);
  for (const auto& t : trees) {
    const Eigen::Vector2d c = t.at_height(1.3).head<2>();
    canvas.circle(c, t.dbh_m / 2, palette(t.id), 2.0);
    canvas.text(c + Eigen::Vector2d(t.dbh_m / 2 + 0.1, 0), std::to_string(t.id), {0, 0, 0}, 11);
  }
  canvas.title(fmt::format("trunks: {} trees", trees.size()));
  canvas.legend({{"points 1.2-1.4 m above the ground", {0.15, 0.15, 0.2}},
                 {"other points", {0.85, 0.87, 0.9}},
                 {"stem at 1.3 m (DBH)", palette(1)}});
  canvas.save_png(path, force);
}

bool is_sequence(const fs::path& input) {
  if (fs::is_directory(input)) return true;
  const std::string ext = io::extension_of(input);
  return input.string().find('*') != std::string::npos || ext == "pcap" || ext == "bag" ||
         ext == "db3" || ext == "mcap";
}

void draw_map(const std::vector<forest::Tree>& trees, const std::vector<Eigen::Vector3d>& path,
              const fs::path& file, bool force) {
  Eigen::Vector2d lo(1e30, 1e30), hi(-1e30, -1e30);
  for (const auto& p : path) lo = lo.cwiseMin(p.head<2>()), hi = hi.cwiseMax(p.head<2>());
  for (const auto& t : trees) {
    const Eigen::Vector2d c = t.at_height(1.3).head<2>();
    lo = lo.cwiseMin(c), hi = hi.cwiseMax(c);
  }
  if (!(lo.x() <= hi.x())) return;
  TopDownCanvas canvas(lo - Eigen::Vector2d(2, 2), hi + Eigen::Vector2d(2, 2));
  std::vector<Eigen::Vector2d> xy;
  for (const auto& p : path) xy.push_back(p.head<2>());
  canvas.polyline(xy, {0.2, 0.2, 0.2}, 2.0);
  for (const auto& t : trees) {
    const Eigen::Vector2d c = t.at_height(1.3).head<2>();
    canvas.circle(c, std::max(t.dbh_m / 2, 0.05), palette(t.id), 2.0);
    canvas.text(c + Eigen::Vector2d(t.dbh_m / 2 + 0.15, 0), std::to_string(t.id), {0, 0, 0}, 10);
  }
  canvas.title(fmt::format("trunk map: {} trees, {} scans", trees.size(), path.size()));
  canvas.legend({{"driven path", {0.2, 0.2, 0.2}}, {"stem at 1.3 m (DBH)", palette(1)}});
  canvas.save_png(file, force);
}

// A sequence: every scan tracked against the trunk map (optionally on the odometry's motion).
void run_sequence(const TrunksOptions& o) {
  const fs::path out(o.out);
  fs::create_directories(out);
  for (const char* n : {"poses.txt", "poses_tum.txt", "trees.csv", "trees.geojson", "trees.png"})
    io::check_writable(out / n, o.force, {fs::path(o.input)});
  fs::path input(o.input);
  std::vector<double> times;
  Pose T_world_first = Pose::Identity();
  bool have_first = false;
  if (fs::is_directory(input) && fs::is_directory(input / "pcd")) {  // a simulator folder
    if (fs::exists(input / "times.txt")) times = io::read_kitti_times(input / "times.txt");
    if (fs::exists(input / "poses.txt")) {
      const auto ref = io::read_kitti_poses(input / "poses.txt");
      if (!ref.empty()) T_world_first = ref[0].pose, have_first = true;
    }
    input = input / "pcd";
  }
  auto source = io::FrameSource::open(input);
  std::unique_ptr<forest::TrunkTracker> tracker;
  std::optional<odometry::LidarOdometry> odo;
  std::optional<SensorModel> sensor;
  Trajectory poses;
  std::vector<Eigen::Vector3d> path;
  Pose odo_prev = Pose::Identity();
  std::size_t tracked = 0;
  while (auto frame = source->next()) {
    PointCloud& cloud = frame->cloud;
    if (!cloud.fields.ring)
      throw Error(
          fmt::format("{}: frame {} has no ring field; tracking needs the scan lines of a "
                      "spinning sensor",
                      o.input, frame->index));
    if (frame->index < times.size()) cloud.stamp_s = times[frame->index];
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
    fmt::print(stderr, "\rframe {} ({:.0f} %): {} trees, {} matched   ", frame->index,
               100 * source->progress(), r.trees, r.matched);
  }
  fmt::print(stderr, "\n");
  if (!tracker) throw Error(o.input + ": no frame");
  const auto trees = tracker->map_trees();
  const io::WriteOptions wo{.overwrite = o.force};
  io::write_kitti_poses(out / "poses.txt", poses, wo);
  io::write_tum(out / "poses_tum.txt", poses, wo);
  io::write_file_atomic(out / "trees.csv", trees_csv(trees, Eigen::Vector3d::Zero()), o.force);
  io::write_file_atomic(out / "trees.geojson", trees_geojson(trees, Eigen::Vector3d::Zero()),
                        o.force);
  draw_map(trees, path, out / "trees.png", o.force);
  fmt::print(
      "{}: {} scans ({} tracked on trunks{}), {:.2f} m; trunk map: {} trees seen in 5 scans or "
      "more -> {}\n",
      o.input, poses.size(), tracked, odo ? ", odometry prior" : "", poses.path_length_m(),
      trees.size(), out.string());
  if (!o.truth.empty()) {
    if (!have_first)
      warn(
          "--truth: no simulator poses.txt next to the frames; the truth is taken in the frame "
          "of the first scan");
    print_scores(trees, read_truth(o.truth, T_world_first.inverse()), path);
  }
}

void run(const TrunksOptions& o) {
  if (is_sequence(o.input)) return run_sequence(o);
  const fs::path out(o.out);
  const std::vector<std::string> names = {"trees.csv", "trees.geojson", "trees.png"};
  fs::create_directories(out);
  for (const auto& n : names) io::check_writable(out / n, o.force, {fs::path(o.input)});
  const PointCloud cloud = io::read_cloud(o.input);
  // A sweep with rings gets the robust ground; a plot file, or a sweep without rings (its trunks
  // come from horizontal slices, as a plot's do), the grid: the ring-less sweep of forest_sloam
  // gave no stack at all on the robust ground.
  segmentation::GroundResult ground;
  const bool sweep = segmentation::check_sweep(cloud).sweep;
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
  draw(cloud, ground.is_ground, result.trees, out / "trees.png", o.force);
  fmt::print("{}: {} points ({}), {} ground; {} scan segments, {} stacks, {} trees -> {}\n",
             o.input, cloud.size(),
             fmt::format("{}, {}", sweep ? "sweep" : "plot",
                         cloud.fields.ring ? "rings" : "horizontal slices"),
             ground.ground_count, result.segments, result.stacks, result.trees.size(),
             out.string());
  if (!o.truth.empty()) print_scores(result.trees, read_truth(o.truth, Pose::Identity()), {});
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
                  "Simulator trees.csv: print precision, recall, DBH RMSE/bias, position RMSE");
  cmd->add_flag("--odometry", o->odometry,
                "Sequence: the seed 002 odometry gives each scan's prior motion");
  cmd->add_option("--sensor", o->sensor, "Sensor preset for a sweep; default from the rings");
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
