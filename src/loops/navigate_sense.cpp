// The navigate loop's senses: one sweep mapped (and the planner's view of the map rebuilt), the
// robot's footprint against the built map (the emergency stop), its tilt (the tilt stop: the IMU,
// here the chassis on the true ground) and the footprint against the truth (the score).

#include <algorithm>
#include <cmath>

#include "fieldlidar/core/rotate_points.hpp"
#include "fieldlidar/loops/navigate_maps.hpp"
#include "fieldlidar/planning/planning_map.hpp"
#include "fieldlidar/sim/motion.hpp"
#include "navigate_loop.hpp"

namespace fieldlidar::loops {

AreaGridRules area_grid_rules(const NavigateConfig& config, const Pose& sensor_pose,
                              const Eigen::Vector2d& robot_xy_m, double mast_m,
                              double blind_radius_m, const Eigen::Vector2d& goal_xy_m,
                              std::span<const Eigen::Vector3d> earlier_sensors_m) {
  const auto& robot = config.fusion.layers.robot;
  const Eigen::Matrix3d R = sensor_pose.rotation();
  return {.seen_no_ground_points = config.seen_no_ground_points,
          .sensor_xy_m = robot_xy_m,
          .sensor_z_m = sensor_pose.translation().z(),
          .sensor_height_m = mast_m,
          .blind_radius_m = blind_radius_m,
          .negative_impassable = config.negative_obstacles_impassable,
          .goal_xy_m = goal_xy_m,
          .goal_clear_m = config.negative_goal_clear_m,
          .drop_band_max_m = config.drop_band_max_m,
          .drop_min_m = robot.max_step_m,
          .drop_min_slope_deg = config.drop_min_slope_deg,
          .drop_radius_m = config.drop_radius_m,
          .blind_drop_clear_m = config.blind_drop_clear_m,
          .ground_normal =
              R *
              Eigen::AngleAxisd(-config.lidar_pitch_deg * M_PI / 180.0, Eigen::Vector3d::UnitY()) *
              Eigen::Vector3d::UnitZ(),
          .sensor_up = R * Eigen::Vector3d::UnitZ(),
          .max_slope_deg = robot.max_slope_deg,
          .earlier_sensors_m = earlier_sensors_m,
          .driven = {}};
}

}  // namespace fieldlidar::loops

namespace fieldlidar::loops::detail {

void Loop::scan() {
  const auto t0 = Clock::now();
  const sim::SimFrame frame = lidar_.scan(t_, poses_->lidar_pose(pose_));
  const Pose placed = poses_->place_sweep(frame.cloud, t_, pose_);
  map_sweep(frame.cloud, placed);
  AreaGridRules rules = area_grid_rules(cfg_, placed, {me().x_m, me().y_m}, mast_m_,
                                        blind_radius_m_, {goal_.x_m, goal_.y_m}, approach_sensors_);
  rules.driven = driven_;
  grid_ = area_grid(map_, area_, rules, drop_marks_);
  use_grid();
  map_updated_ = true;
  ++r_.scans;
  scan_ms_ += ms_since(t0);
}

void Loop::map_sweep(const PointCloud& sweep, const Pose& T) {
  if (cfg_.lidar_pitch_deg == 0.0) {
    map_.add_scan(sweep, sensor_, T);
    return;
  }
  // The mount's pitch is a known extrinsic: levelled by it, the sweep meets the ground
  // segmentation as a level sensor's does.
  const Eigen::AngleAxisd mount(cfg_.lidar_pitch_deg * M_PI / 180.0, Eigen::Vector3d::UnitY());
  PointCloud level = sweep;
  rotate_points(level, mount.toRotationMatrix().cast<float>());
  map_.add_scan(level, sensor_, T * mount.inverse());
}

void Loop::use_grid() {
  if (!felt_.empty()) {
    auto imp = grid_.layer(terrain::layer::kImpassable);
    for (std::size_t i = 0; i < felt_.size(); ++i)
      if (felt_[i]) imp[i] = 1.f;
  }
  blocked_ = known_blocked(grid_);
  check_map_ = std::make_unique<planning::PlanningMap>(grid_, robot_, planner_cfg_.map);
}

double Loop::chassis_tilt_rad(const Pose2& pose) const {
  const Eigen::Vector3d up =
      sim::pose_on_ground(scene_, {pose.x_m, pose.y_m}, pose.yaw_rad).rotation() *
      Eigen::Vector3d::UnitZ();
  return std::acos(std::clamp(up.z(), -1.0, 1.0));
}

bool Loop::tilt_stop(double v_m_s, double tilt) {
  if (!(cfg_.tilt_stop_deg > 0) || std::abs(v_m_s) < 1e-6) return false;
  const double before = tilt_rad_;
  tilt_rad_ = tilt;
  // Over the limit and tilting further: a move that levels the robot (backing out) goes on.
  if (!(tilt > cfg_.tilt_stop_deg * M_PI / 180.0) || !(tilt > before + 1e-3)) return false;
  // The leading half of the footprint (where the robot is, by its own pose), ahead of its centre
  // in the direction it drives.
  const double sign = v_m_s > 0 ? 1.0 : -1.0, quarter = 0.25 * robot_.length_m;
  const Pose2 lead{me().x_m + sign * quarter * std::cos(me().yaw_rad),
                   me().y_m + sign * quarter * std::sin(me().yaw_rad), me().yaw_rad};
  felt_.resize(area_.cell_count(), 0);
  for (long c : planning::rectangle_cells(area_, lead, quarter, 0.5 * robot_.width_m))
    if (c >= 0) felt_[std::size_t(c)] = 1;
  use_grid();
  return true;
}

bool Loop::enters_known_blocked(const Pose2& next) const {
  return footprint_enters_blocked(area_, blocked_, footprint_cells(area_, me(), robot_), next,
                                  robot_);
}

bool Loop::on_truth_impassable(const Pose2& pose, double shrink_m) const {
  for (long c : planning::rectangle_cells(area_, pose, 0.5 * robot_.length_m - shrink_m,
                                          0.5 * robot_.width_m - shrink_m))
    if (c < 0 || truth_blocked_[std::size_t(c)]) return true;
  return false;
}

double Loop::truth_impassable_depth_m(const Pose2& pose) const {
  int cm = 0;  // on_truth_impassable(pose, cm / 100) holds; the footprint's half width bounds it
  for (int step = 32; step > 0; step /= 2)
    if (cm + step < int(50.0 * robot_.width_m) && on_truth_impassable(pose, (cm + step) / 100.0))
      cm += step;
  return cm / 100.0;
}

}  // namespace fieldlidar::loops::detail
