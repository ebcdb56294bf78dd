// The navigate loop's senses: one sweep mapped (and the planner's view of the map rebuilt), the
// robot's footprint against the built map (the emergency stop) and against the truth (the score).

#include "fieldlidar/loops/navigate_maps.hpp"
#include "fieldlidar/planning/planning_map.hpp"
#include "navigate_loop.hpp"

namespace fieldlidar::loops::detail {

void Loop::scan() {
  const auto t0 = Clock::now();
  const sim::SimFrame frame = lidar_.scan(t_, poses_->lidar_pose(pose_));
  const Pose placed = poses_->place_sweep(frame.cloud, t_, pose_);
  map_.add_scan(frame.cloud, sensor_, placed);
  grid_ = area_grid(map_, area_,
                    {.seen_no_ground_points = cfg_.seen_no_ground_points,
                     .sensor_xy_m = {me().x_m, me().y_m},
                     .sensor_z_m = placed.translation().z(),
                     .sensor_height_m = mast_m_,
                     .blind_radius_m = blind_radius_m_,
                     .negative_impassable = cfg_.negative_obstacles_impassable,
                     .goal_xy_m = {goal_.x_m, goal_.y_m},
                     .goal_clear_m = cfg_.negative_goal_clear_m,
                     .drop_band_max_m = cfg_.drop_band_max_m,
                     .drop_min_m = robot_.max_step_m,
                     .drop_min_slope_deg = cfg_.drop_min_slope_deg,
                     .drop_radius_m = cfg_.drop_radius_m,
                     .blind_drop_clear_m = cfg_.blind_drop_clear_m,
                     .ground_normal = placed.rotation() *
                                      Eigen::AngleAxisd(-cfg_.lidar_pitch_deg * M_PI / 180.0,
                                                        Eigen::Vector3d::UnitY()) *
                                      Eigen::Vector3d::UnitZ(),
                     .sensor_up = placed.rotation() * Eigen::Vector3d::UnitZ(),
                     .max_slope_deg = robot_.max_slope_deg,
                     .earlier_sensors_m = approach_sensors_},
                    drop_marks_);
  blocked_ = known_blocked(grid_);
  check_map_ = std::make_unique<planning::PlanningMap>(grid_, robot_, planner_cfg_.map);
  map_updated_ = true;
  ++r_.scans;
  scan_ms_ += ms_since(t0);
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
