#pragma once
// The navigate loop's state in one object (navigate.hpp): its steps are members, defined by idea in
// navigate.cpp (set-up and entry), navigate_run.cpp (the control loop), navigate_replan.cpp (when
// and how to plan) and navigate_sense.cpp (the sweep, the footprint checks). Private to loops/.

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "fieldlidar/loops/navigate.hpp"
#include "fieldlidar/loops/navigate_poses.hpp"
#include "fieldlidar/planning/planner_for_robot.hpp"
#include "fieldlidar/sim/lidar_simulator.hpp"

namespace fieldlidar::loops::detail {

using planning::PlanStatus;
using planning::Pose2;
using Clock = std::chrono::steady_clock;

inline double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

/// The loop's state in one object; each step is a member so that run() reads like the loop.
class Loop {
 public:
  Loop(const sim::Scene& scene, const SensorModel& sensor, const NavigateConfig& config);

  NavigateResult run(const Pose2& start, const Pose2& goal);

 private:
  void score_truth_plan();
  void scan();
  /// Fuses a sweep taken at `T` (the sensor's pose, the mount's pitch included) into the map, in
  /// the frame of a level mount at the sensor.
  void map_sweep(const PointCloud& sweep, const Pose& T);
  /// The approach's sweeps (NavigateConfig::approach_m) fused into the map before the first sweep
  /// at the start; returns how many.
  std::size_t approach();
  std::string replan_trigger();
  void plan(const std::string& trigger);
  /// Detour hold (NavigateConfig::detour_hold_ratio), before a plan for `trigger` is searched:
  /// true when the held plan goes on (resumed, or still short of its hold point).
  bool hold_before_plan(const std::string& trigger);
  /// After a successful plan of `length_m`: true when the robot holds to the current plan
  /// instead (the plan is recorded, not followed).
  bool hold_instead_of(double length_m);
  /// A periodic re-plan's `candidate` is taken only when it costs less than the rest of the
  /// current plan by NavigateConfig::replan_switch_gain: true when the robot keeps its plan.
  bool keeps_its_plan(const planning::Path& candidate) const;
  /// The planner's cost of each step of `path` on the map of the moment (check_map_).
  std::vector<double> step_costs(const planning::Path& path) const;
  /// What the rest of the followed plan (past the follower's index) costs on that map.
  double rest_cost() const;
  /// The rest of held_ from the sample nearest the robot: its index, the first blocked sample
  /// after it (nullopt: none), and the length to that sample and to the end.
  struct HeldRest {
    std::size_t from = 0;
    std::optional<std::size_t> blocked;
    double to_block_m = 0, to_end_m = 0;
  };
  HeldRest held_rest() const;
  /// The held plan from sample `from` up to hold_stop_m before sample `block` (the whole rest
  /// when `block` is nullopt), to the follower; false when too little of it is left.
  bool follow_held(std::size_t from, std::optional<std::size_t> block);
  /// The cold start's straight creep (NavigateConfig::start_creep_m) as the first plan; false
  /// when it is off or both lanes are blocked.
  bool start_creep();
  /// True when the next pose's footprint would enter a cell the map knows to be impassable that
  /// the robot does not already stand on.
  bool enters_known_blocked(const Pose2& next) const;
  /// NavigateConfig::tilt_stop_deg: true when the robot, moving at `v_m_s`, stands tilted
  /// (`tilt_rad`, chassis_tilt_rad of its true pose) more than that and more than at its last
  /// driving step; the cells under the leading half of its
  /// footprint are then felt_ and the map is updated at once.
  bool tilt_stop(double v_m_s, double tilt_rad);
  /// The chassis' tilt (rad) resting on the true ground at `pose` (what its IMU reads).
  double chassis_tilt_rad(const Pose2& pose) const;
  /// The guessed drops (drop_marks_, not yet looked_ at) under the footprint of the plan to
  /// `target` found with them taken as unknown; empty when there is no such plan.
  std::vector<std::size_t> guesses_in_the_way(const Pose2& target) const;
  /// NavigateConfig::guess_looks: when the guesses alone cut `target` off, a plan to the nearest
  /// free pose from which they all lie beyond the blind disk is followed (look_trip_); true
  /// when one was.
  bool look_at_guesses(const Pose2& target);
  /// grid_ with the felt_ cells impassable, then blocked_ and check_map_ from it.
  void use_grid();
  /// The footprint at `pose`, shrunk by `shrink_m` on every side, overlaps a truth-impassable
  /// cell (or leaves the area).
  bool on_truth_impassable(const Pose2& pose, double shrink_m = 0.0) const;
  /// The gap (m) between the footprint at `pose` and the nearest obstacle disc the truth counts
  /// (negative: overlapping; NavigateResult::min_obstacle_gap_m).
  double obstacle_gap_m(const Pose2& pose) const;
  /// NavigateResult::max_impassable_depth_m at a pose whose footprint is on a truth-impassable
  /// cell (on_truth_impassable).
  double truth_impassable_depth_m(const Pose2& pose) const;
  void finish(NavigateOutcome outcome, std::string reason, NavigateState state) {
    r_.outcome = outcome;
    r_.reason = std::move(reason);
    state_ = state;
    done_ = true;
  }

  const sim::Scene& scene_;
  SensorModel sensor_;  ///< mounted at the scene's mast height (the ground's blind radius)
  NavigateConfig cfg_;
  terrain::RobotConfig robot_;
  planning::PlannerConfig planner_cfg_;
  sim::LidarSimulator lidar_;
  terrain::TerrainMap map_;
  planning::PathFollower follower_;
  GridGeometry area_;
  Grid2D truth_;
  std::vector<std::uint8_t> truth_blocked_, blocked_;
  Grid2D grid_;                           ///< the fused map on the area (planner input)
  std::vector<std::uint8_t> drop_marks_;  ///< drop bands seen so far (area_grid, mark_drop_bands)
  std::vector<std::uint8_t> felt_;        ///< cells the tilt stop found impassable (for good)
  std::vector<std::uint8_t> driven_;      ///< cells the robot has stood on (mark_driven)
  std::vector<std::uint8_t> looked_;      ///< guessed drops a look went to see (look_at_guesses)
  std::vector<Eigen::Vector3d> approach_sensors_;     ///< the approach's sensor positions (m)
  std::unique_ptr<planning::PlanningMap> check_map_;  ///< the planner's view of grid_
  std::vector<double> step_costs_;  ///< the current plan's step costs when it was made
  NavigateResult r_;
  Pose2 pose_, goal_;                   ///< pose_: the truth (motion, scoring)
  std::optional<NavigatePoses> poses_;  ///< the pose the robot works with (me())
  const Pose2& me() const { return poses_->estimate(); }
  double t_ = 0, v_ = 0, last_plan_t_ = -1e9, scan_ms_ = 0, plan_ms_ = 0;
  double tilt_rad_ = 0;        ///< the chassis' tilt at the last driving step (rad)
  double blind_radius_m_ = 0;  ///< no ground return nearer the sensor than this (m)
  double mast_m_ = 0;          ///< the sensor's height above the ground under the robot (m)
  bool map_updated_ = false, done_ = false;
  bool creeping_ = false;   ///< following the cold start's creep
  bool look_trip_ = false;  ///< following a plan to a viewpoint (look_at_guesses)
  double looked_rad_ = 0;   ///< turned in place so far by the start look (start_look_rad)
  bool looking() const { return looked_rad_ < cfg_.start_look_rad; }
  std::string pending_;  ///< a re-plan asked for by the last control step
  planning::Path held_;  ///< the plan held while a detour is put off (empty: none)
  int unreachable_votes_ = 0, planner_failures_ = 0, off_goal_plans_ = 0;
  NavigateState state_ = NavigateState::kPlanning;
};

}  // namespace fieldlidar::loops::detail
