#include "support/navigate_output.hpp"

#include <cmath>

#include <fmt/core.h>

#include "fieldlidar/io/file_util.hpp"
#include "fieldlidar/io/nav2_map.hpp"
#include "fieldlidar/planning/planning_map.hpp"
#include "support/canvas.hpp"
#include "support/planar_paths.hpp"

namespace fieldlidar::app {
namespace {

namespace fs = std::filesystem;
namespace L = terrain::layer;

nlohmann::json number_or_null(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nullptr;
}

nlohmann::json pose_json(const planning::Pose2& p) {
  return {p.x_m, p.y_m, p.yaw_rad};
}

std::string plans_csv(const loops::NavigateResult& r) {
  std::string s = "plan,t_s,trigger,status,x_m,y_m,yaw_rad,reverse\n";
  auto add = [&](const std::string& id, double t, const std::string& trigger,
                 const std::string& status, const planning::Path& path) {
    for (const auto& p : path)
      s += fmt::format("{},{:.2f},{},{},{:.4f},{:.4f},{:.5f},{}\n", id, t, trigger, status,
                       p.pose.x_m, p.pose.y_m, p.pose.yaw_rad, int(p.reverse));
  };
  add("truth", 0.0, "truth", planning::to_string(r.truth_status), r.truth_path);
  for (std::size_t k = 0; k < r.plans.size(); ++k)
    add(std::to_string(k), r.plans[k].t_s, r.plans[k].trigger,
        planning::to_string(r.plans[k].status), r.plans[k].path);
  return s;
}

nlohmann::json line(const planning::Path& path) {
  nlohmann::json c = nlohmann::json::array();
  for (const auto& p : path) c.push_back({p.pose.x_m, p.pose.y_m});
  return c;
}

std::string plans_geojson(const loops::NavigateResult& r) {
  nlohmann::json fc = {{"type", "FeatureCollection"}, {"features", nlohmann::json::array()}};
  auto feature = [&](nlohmann::json props, nlohmann::json geometry) {
    props["frame"] = "map (the scene's world frame, m)";
    fc["features"].push_back(
        {{"type", "Feature"}, {"properties", std::move(props)}, {"geometry", std::move(geometry)}});
  };
  if (!r.truth_path.empty())
    feature({{"name", "plan on the truth map"}, {"length_m", r.truth_length_m}},
            {{"type", "LineString"}, {"coordinates", line(r.truth_path)}});
  for (std::size_t k = 0; k < r.plans.size(); ++k)
    if (r.plans[k].path.size() >= 2)
      feature({{"name", "plan " + std::to_string(k)},
               {"t_s", r.plans[k].t_s},
               {"trigger", r.plans[k].trigger},
               {"length_m", r.plans[k].length_m}},
              {{"type", "LineString"}, {"coordinates", line(r.plans[k].path)}});
  nlohmann::json driven = nlohmann::json::array();
  for (const auto& p : r.driven) driven.push_back({p.x_m, p.y_m});
  if (driven.size() >= 2)
    feature({{"name", "driven"}, {"length_m", r.driven_length_m}},
            {{"type", "LineString"}, {"coordinates", driven}});
  for (const auto& [name, p] : {std::pair{"start", r.start}, std::pair{"goal", r.goal}})
    feature({{"name", name}, {"yaw_rad", p.yaw_rad}},
            {{"type", "Point"}, {"coordinates", {p.x_m, p.y_m}}});
  return fc.dump(1) + "\n";
}

// The built map's cells that disagree with the truth: blocked though passable (obstacles read
// wider), passable though impassable (a danger missed).
constexpr Rgb kBlockedPassable{0.45, 0.35, 0.55};
constexpr Rgb kMissedImpassable{1.0, 0.85, 0.0};

/// Two panels side by side: the truth (left) and the map built by the robot (right), each with the
/// plans, the plan on the truth and the driven path.
void draw(const loops::NavigateResult& r, const std::string& title, const fs::path& png,
          bool force) {
  const GridGeometry& g = r.truth.geometry();
  const Eigen::Vector2d size(g.width * g.resolution_m, g.height * g.resolution_m);
  const Eigen::Vector2d shift(size.x() + 2.0, 0.0);
  TopDownCanvas canvas(g.origin_m, g.origin_m + shift + size, 1800);
  const auto passable = r.truth.layer("passable");
  const auto slope = r.truth.layer("slope_deg");
  GridGeometry right = g;
  right.origin_m += shift;
  const auto tau = r.built_map.layer(L::kTraversability);
  const auto imp = r.built_map.layer(L::kImpassable);
  const auto pts = r.built_map.layer(L::kPoints);
  for (int iy = 0; iy < g.height; ++iy)
    for (int ix = 0; ix < g.width; ++ix) {
      const std::size_t i = g.linear_index(ix, iy);
      const double s = std::clamp(slope[i] / 25.0, 0.0, 1.0);
      canvas.cell(
          g, ix, iy,
          passable[i] < 0.5f ? Rgb{0, 0, 0} : Rgb{1.0 - 0.4 * s, 1.0 - 0.2 * s, 1.0 - 0.4 * s});
      const planning::CellRead read = planning::read_cell(tau[i], imp[i], pts[i]);
      const bool free_in_truth = passable[i] >= 0.5f;
      const double t = read == planning::CellRead::kPassable ? tau[i] : 0.0;
      // Where the built map disagrees with the truth (MapAgreement, over the whole map here).
      canvas.cell(right, ix, iy,
                  read == planning::CellRead::kBlocked
                      ? (free_in_truth ? kBlockedPassable : Rgb{0, 0, 0})
                  : read == planning::CellRead::kUnknown ? Rgb{0.65, 0.65, 0.65}
                  : !free_in_truth                       ? kMissedImpassable
                                   : Rgb{1.0 - 0.5 * t, 1.0 - 0.2 * t, 1.0 - 0.5 * t});
    }
  auto both = [&](const std::vector<Eigen::Vector2d>& pts_m, const Rgb& c, double w) {
    canvas.polyline(pts_m, c, w);
    std::vector<Eigen::Vector2d> moved;
    for (const auto& p : pts_m) moved.push_back(p + shift);
    canvas.polyline(moved, c, w);
  };
  auto xy = [](const planning::Path& p) {
    std::vector<Eigen::Vector2d> v;
    for (const auto& s : p) v.emplace_back(s.pose.x_m, s.pose.y_m);
    return v;
  };
  for (const auto& p : r.plans) both(xy(p.path), {0.55, 0.7, 1.0}, 1.0);
  both(xy(r.truth_path), {0.1, 0.7, 0.1}, 2.0);
  std::vector<Eigen::Vector2d> driven;
  for (const auto& p : r.driven) driven.emplace_back(p.x_m, p.y_m);
  both(driven, {0.85, 0.1, 0.1}, 2.0);
  for (const auto& row : r.rows)
    if (row.footprint_on_impassable) canvas.dot({row.x_m, row.y_m}, {1.0, 0.0, 1.0}, 3.0);
  for (const auto& row : r.rows)  // a rock met or a wheel down a wall: drawn over the cells
    if (row.obstacle_gap_m < 0.0 || row.tilted_over)
      canvas.dot({row.x_m, row.y_m}, {1.0, 0.55, 0.0}, 4.0);
  for (const Eigen::Vector2d& o : {Eigen::Vector2d(Eigen::Vector2d::Zero()), shift}) {
    canvas.arrow(Eigen::Vector2d(r.start.x_m, r.start.y_m) + o, r.start.yaw_rad, 1.5, {0, 0.5, 0});
    canvas.arrow(Eigen::Vector2d(r.goal.x_m, r.goal.y_m) + o, r.goal.yaw_rad, 1.5, {0.7, 0, 0});
  }
  // Top right of the truth panel: the legend takes its top left.
  canvas.text(g.origin_m + Eigen::Vector2d(size.x() - 4.0, size.y() - 1.0), "truth", {0, 0, 0.6},
              16);
  canvas.text(right.origin_m + Eigen::Vector2d(0.5, size.y() - 1.0), "built by the robot",
              {0, 0, 0.6}, 16);
  canvas.title(title);
  canvas.legend({{"impassable", {0, 0, 0}},
                 {"unknown (built map)", {0.65, 0.65, 0.65}},
                 {"plans on the built map", {0.55, 0.7, 1.0}},
                 {"plan on the truth", {0.1, 0.7, 0.1}},
                 {"driven", {0.85, 0.1, 0.1}},
                 {"footprint on truth-impassable", {1.0, 0.0, 1.0}},
                 {"on an obstacle, or tipped", {1.0, 0.55, 0.0}},
                 {"built map: blocked, passable in truth", kBlockedPassable},
                 {"built map: passable, impassable in truth", kMissedImpassable}});
  canvas.save_png(png, force);
}

/// The map the robot built (the planner's input at the end) as a nav2 map_server map in the
/// scene's frame, the cost kept ("scale": pixel = 254 x tau, impassable black, unknown grey):
/// `fieldlidar plan --map DIR` plans on it again.
void write_built_map(const loops::NavigateResult& r, const fs::path& dir, bool force) {
  Grid2D map(r.built_map.geometry());
  const auto tau = r.built_map.layer(L::kTraversability);
  const auto imp = r.built_map.layer(L::kImpassable);
  auto out = map.add_layer("tau", NAN);
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = imp[i] > 0.5f ? 0.f : tau[i];
  io::Nav2MapConfig nav;
  nav.mode = "scale";
  const io::Nav2Map nav2 = io::encode_nav2_map(map, "tau", "built_map.pgm", nav);
  io::write_file_atomic(dir / "built_map.pgm", nav2.pgm, force);
  io::write_file_atomic(dir / "built_map.yaml", nav2.yaml, force);
}

}  // namespace

std::vector<fs::path> navigate_files(const fs::path& dir) {
  return {dir / "plans.csv",        dir / "plans.geojson", dir / "path.csv",
          dir / "navigate_log.csv", dir / "summary.json",  dir / "navigate.png",
          dir / "built_map.yaml",   dir / "built_map.pgm"};
}

nlohmann::json navigate_settings(const loops::NavigateConfig& cfg) {
  const auto& robot = cfg.fusion.layers.robot;
  return {{"robot",
           {{"length_m", robot.length_m},
            {"width_m", robot.width_m},
            {"max_slope_deg", robot.max_slope_deg},
            {"max_step_m", robot.max_step_m},
            {"min_turn_radius_m", robot.min_turn_radius_m}}},
          {"cell_m", cfg.fusion.layers.cell_m},
          {"lidar_pitch_deg", cfg.lidar_pitch_deg},
          {"start_look_rad", cfg.start_look_rad},
          {"approach_m", cfg.approach_m},
          {"blind_drop_clear_m", cfg.blind_drop_clear_m},
          {"tilt_stop_deg", cfg.tilt_stop_deg},
          {"guess_looks_allowed", cfg.guess_looks},
          {"noise_seed", cfg.sim_seed}};
}

nlohmann::json navigate_summary(const loops::NavigateResult& r) {
  nlohmann::json j;
  j["outcome"] = loops::to_string(r.outcome);
  j["reason"] = r.reason;
  j["start"] = pose_json(r.start);
  j["goal"] = pose_json(r.goal);
  j["driven_length_m"] = r.driven_length_m;
  j["truth_plan_status"] = planning::to_string(r.truth_status);
  j["truth_plan_length_m"] = number_or_null(r.truth_length_m);
  j["length_ratio"] = number_or_null(r.length_ratio);
  j["frames"] = r.rows.size();
  j["frames_on_impassable"] = r.frames_on_impassable;
  j["max_impassable_depth_m"] = r.max_impassable_depth_m;
  j["frames_on_obstacles"] = r.frames_on_obstacles;
  j["min_obstacle_gap_m"] = number_or_null(r.min_obstacle_gap_m);
  j["max_tilt_deg"] = r.max_tilt_deg;
  const loops::MapAgreement& m = r.map_agreement;
  j["built_map_vs_truth"] = {
      {"radius_m", m.radius_m},
      {"known_cells", m.known_cells},
      {"truth_passable", m.truth_passable},
      {"passable_blocked", m.passable_blocked},
      {"passable_blocked_beside_impassable", m.passable_blocked_beside_impassable},
      {"impassable_passable", m.impassable_passable}};
  j["plans"] = r.plans.size();
  j["replans"] = r.replans;
  j["safety_stops"] = r.safety_stops;
  j["tilt_stops"] = r.tilt_stops;
  j["guess_looks"] = r.guess_looks;
  j["escapes"] = r.escapes;
  j["plans_put_off"] = r.plans_put_off;
  j["approach_sweeps"] = r.approach_sweeps;
  j["blind_radius_m"] = r.blind_radius_m;
  j["scans"] = r.scans;
  j["duration_s"] = r.duration_s;
  j["wall_s"] = r.wall_s;
  j["mean_scan_ms"] = r.scan_ms;
  j["mean_plan_ms"] = r.plan_ms;
  j["pose_source"] = r.pose_source == loops::PoseSource::kTruth
                         ? "truth (the simulator's poses place the scans)"
                         : "odometry (LiDAR odometry with IMU and wheels places the scans; the "
                           "robot plans and drives by it)";
  j["max_pose_error_m"] = r.max_pose_error_m;
  j["odometry_unregistered_sweeps"] = r.odometry_unregistered;
  nlohmann::json triggers = nlohmann::json::object();
  for (const auto& p : r.plans) triggers[p.trigger] = triggers.value(p.trigger, 0) + 1;
  j["plan_triggers"] = triggers;
  return j;
}

void write_navigate_run(const fs::path& dir, const loops::NavigateResult& r,
                        const nlohmann::json& extra, const std::string& title, bool force) {
  nlohmann::json j = navigate_summary(r);
  j.update(extra);
  const planning::Path last = r.plans.empty() ? planning::Path{} : r.plans.back().path;
  io::write_file_atomic(dir / "plans.csv", plans_csv(r), force);
  io::write_file_atomic(dir / "plans.geojson", plans_geojson(r), force);
  io::write_file_atomic(dir / "path.csv", path_csv(last), force);
  io::write_file_atomic(dir / "navigate_log.csv", loops::navigate_log_csv(r.rows), force);
  io::write_file_atomic(dir / "summary.json", j.dump(1) + "\n", force);
  draw(r, title, dir / "navigate.png", force);
  write_built_map(r, dir, force);
}

}  // namespace fieldlidar::app
