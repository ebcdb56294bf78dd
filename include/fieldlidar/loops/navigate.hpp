#pragma once
/// \file Seed 004 in closed loop with the simulator (issue 17, item 5): the robot scans with its
/// LiDAR, fuses the scans into the traversability map (terrain::TerrainMap, placed by the true
/// poses, or by the robot's LiDAR odometry: NavigateConfig::pose_source), plans on that map with
/// Hybrid A*, follows its plan by pure pursuit, and re-plans when
/// the map blocks its path, makes the rest of it costlier, or a fixed period has passed. Map frame
/// = the scene's world frame; m, s, rad.
///
/// Unknown cells are planned through optimistically (at traversability unknown_tau, 1 by
/// default: no costlier than the best known ground, so no detour is made just to stay on mapped
/// ground) and learnt as the robot comes close; the robot never moves into a cell the map knows
/// to be impassable: before every control step its exact footprint at the next pose is checked
/// against the built map, and a step that would enter a known-impassable cell is not taken
/// (emergency stop and re-plan). A cell seen well (seen_no_ground_points returns) in which the
/// map found no ground is not unknown but impassable. A goal whose footprint the map blocks is
/// moved to the nearest free pose within goal_tolerance_m - 0.1 m (the map's obstacle halo can
/// cover a goal beside a bush). A goal is unreachable when, on two successive map updates, the
/// whole search space (unknown cells included) holds no path or no pose that near the goal is
/// free.

#include <cstdint>
#include <string>
#include <vector>

#include "fieldlidar/core/grid2d.hpp"
#include "fieldlidar/core/sensor_model.hpp"
#include "fieldlidar/loops/navigate_maps.hpp"
#include "fieldlidar/loops/pose_source.hpp"
#include "fieldlidar/planning/hybrid_astar.hpp"
#include "fieldlidar/planning/path_follower.hpp"
#include "fieldlidar/sim/scene.hpp"
#include "fieldlidar/terrain/terrain_map.hpp"

namespace fieldlidar::loops {

enum class NavigateOutcome {
  kArrived,      ///< at the goal within the tolerances
  kUnreachable,  ///< the map shows no way to the goal
  kFailed,       ///< time limit, repeated safety stops, or a planner failure
};
enum class NavigateState { kPlanning, kDriving, kSafetyStop, kArrived, kUnreachable, kFailed };
const char* to_string(NavigateOutcome outcome);
const char* to_string(NavigateState state);

/// The planner's defaults with unknown cells at tau 1 (optimistic: see the file comment) and
/// searches never hurried (late_expansions 0).
planning::PlannerConfig navigate_planner_config();

/// The fused map's defaults with the ground segmentation's levelling off: the robot's LiDAR is
/// fixed to its chassis (a pitched mount is levelled by its known extrinsic first), so the
/// sweep's own frame is the ground's under the robot. Levelled to the plane of the ground out to
/// 20 m instead, a robot standing on a hill's foot saw the foot round it tilted by the hill's
/// slope, and its lowest ring's returns there (2-3 m out on a VLP-32C) were left out of the
/// ground and read as obstacles round the start. Navigate pairs, seeds 2-21, with levelling ->
/// without: VLP-32C 172 -> 180 of 184 arrive, VLP-16 180 -> 180 (docs/navigate.md).
/// Cells of 0.5 m (fusion.layers.cell_m; `fieldlidar navigate --cell`): 0.25 m cells plan gaps
/// and halos finer and drive shorter, but a robot switched on in open level ground knows no cell
/// of them (docs/navigate.md, "Finer cells").
terrain::FusionConfig navigate_fusion_config();

struct NavigateConfig {
  /// Map fusion; fusion.layers.robot is the robot (footprint, limits, R_min).
  terrain::FusionConfig fusion = navigate_fusion_config();
  /// The planner; its min_turn_radius_m is taken from the robot. Unknown cells at tau 1.
  planning::PlannerConfig planner = navigate_planner_config();
  /// The follower; its min_turn_radius_m is taken from the robot.
  planning::FollowerConfig follower;
  /// A cell with this many returns but no traversability is impassable (seen, no ground: a
  /// slope too steep for the ground segmentation, a wall); see area_grid.
  int seen_no_ground_points = 30;
  /// A likely negative obstacle of the fused map (a trench shadow not seen yet:
  /// terrain::NegativeObstacleConfig, fusion.negative_obstacles) is planned as impassable, not
  /// as unknown.
  bool negative_obstacles_impassable = true;
  /// ... but not within this distance (m) of the goal (see area_grid): the goal's footprint's
  /// half-diagonal (0.55 m), the goal tolerance and a cell. Seed 0 round_hill without the detour
  /// hold: a trench mark by the goal made it unreachable (1.342 before the marks).
  double negative_goal_clear_m = 1.35;
  /// The foot of a step down seen from above (see mark_drop_bands): cells without a return on a
  /// line between ground cells at most drop_band_max_m apart (m) whose heights differ by more
  /// than the robot's max_step_m and by a slope steeper than drop_min_slope_deg, seen beyond the
  /// blind disk and within drop_radius_m of the robot (m), are impassable until seen; 0: off.
  double drop_band_max_m = 3.0;
  double drop_min_slope_deg = 0.0;
  double drop_radius_m = 12.0;
  /// Drops hidden in the blind disk (see mark_blind_drops): unseen cells whose centres lie from
  /// this distance (m) of the robot out to the first ground seen beyond the blind disk are
  /// impassable until seen when that ground lies lower than the ground the robot stands on by
  /// more than its max_step_m and does not lead back up to it; 0: off. 1 m: the footprint's
  /// half-diagonal (0.55 m), half a cell's diagonal and 0.1 m, so that no mark lies under the
  /// robot as it turns in place.
  double blind_drop_clear_m = 1.0;
  /// Ground the robot has driven over is no guess: the cells whose centres its footprint has
  /// covered (by its own pose) carry no drop mark (mark_drop_bands, mark_blind_drops), whatever
  /// later sweeps' shadows suggest; the footprint clearing of a costmap. Evidence (returns,
  /// the tilt stop's felt cells) still blocks them. Found on seed 14 p3 (random pairs): started
  /// on the hill's 20 deg east flank, the robot backed over cells that the blind-drop rule then
  /// marked from its next poses, and 31 emergency stops wedged it between them.
  bool driven_clears_guesses = true;
  /// Tilt stop: the robot's attitude (its IMU; here the chassis resting on the true ground)
  /// tilted more than this (deg) while driving is ground the map missed (a ditch's wall in the
  /// blind disk): the robot stops, the cells under the leading half of its footprint become
  /// impassable for good, and it plans again (out by the shortest free move first). 0: off.
  double tilt_stop_deg = 30.0;
  /// Look before giving up: a goal cut off only by blind drops (mark_blind_drops' cells, unseen
  /// for the blind disk alone) is not reported unreachable before the robot has driven, over
  /// ground its map lets it cross, to the nearest free pose on rings round those cells
  /// (guess_look_margin_m to guess_look_margin_m + guess_look_depth_m beyond the blind disk, m)
  /// from which each lies guess_look_margin_m beyond the blind disk and at most twice
  /// guess_look_depth_m farther, and planned again there; at most this many looks per drive
  /// (0: off). The cells a look went to see are taken as they are then. The drop bands are not
  /// looked at: their cells lie in the shadow of a lip, which no pose above it sees into.
  int guess_looks = 2;
  double guess_look_margin_m = 1.0;
  double guess_look_depth_m = 3.0;
  /// Cells never seen within this distance (m) of the robot (beyond its blind disk) are shadows,
  /// planned at shadow_tau rather than as unknown (see cost_shadows); 0: off. Off by default: at
  /// 12 m on the seed-0 pairs it shortened the drive round the ditch (ratio 1.357 -> 1.233) but
  /// sent other drives along rocks the map misses (round_hill 0 -> 13 frames on truth-impassable
  /// cells) and made round_terrace end unreachable.
  double shadow_radius_m = 0.0;
  double shadow_tau = 0.3;
  /// Cold start: the LiDAR sees no ground within its blind disk (mounting height / tan(lowest
  /// beam), 4.5 m for a VLP-16 at 1.2 m), so a rock beside the start is unseen until the robot
  /// has moved away from it. The robot first creeps straight (forward, or backwards when the goal
  /// lies behind it), at creep_speed_m_s, for this distance (m; < 0: one blind radius, after which
  /// every cell beside the start pose has been seen from a second pose; 0: off), stopping early
  /// before a known-impassable cell, then plans. Off by default: it moves the blind drive rather
  /// than removing it. On the seed-0 pairs it took ne_to_hill off the rock beside its start (53 ->
  /// 15 frames on truth-impassable cells, the 15 from another rock) but on the held-out seed-1
  /// pairs it drove round_terrace into the terrace's unseen cliff (33 -> 73 frames) and added 19
  /// and 17 frames on round_hill and diagonal, and it lengthens drives whose goal is not ahead.
  double start_creep_m = 0.0;
  double creep_speed_m_s = 0.5;
  /// The LiDAR mount's pitch about the robot's y axis (deg, positive: nose down; the mount's
  /// height is the scene's sensor height). Pitched forward by p, the lowest beam (-15 deg on a
  /// VLP-16) meets the ground at h / tan(15 + p) ahead (2.6 m at 10 deg on the 1.2 m mast rather
  /// than 4.5 m) and h / tan(15 - p) behind (13.7 m). Level by default: see start_look_rad.
  double lidar_pitch_deg = 0.0;
  /// Cold start: turn in place (counter-clockwise, at look_yaw_rate_rad_s) this much (rad)
  /// before the first plan, so that a pitched LiDAR sweeps its near view round the start; 0: off.
  /// The turn stops before a known-impassable cell, but its corners sweep a disc of the
  /// footprint's half-diagonal (0.55 m) that no roof LiDAR sees. Off by default: with
  /// lidar_pitch_deg 10 and a full turn (6.3 rad), the seed-0 pairs round_ditch 1.223 -> 1.064
  /// and round_terrace 1.191 -> 1.062, held-out seed 1 round_ditch 1.175 -> 1.078, round_hill
  /// 1.248 -> 1.168, round_terrace 33 -> 0 frames on truth-impassable cells; but ne_to_hill
  /// (seed 0) turned onto the rock 0.4 m beside its chassis (36 frames) and ended unreachable
  /// (its goal on the hill's flank blocked as seen from the west), and at 8 or 12 deg the
  /// round_terrace drives grew (seed 0: 1.296 at both; seed 1: 1.660 at 8 deg, failed at 12):
  /// the gains do not hold across the pitch, nor across the sensor-noise seed (sim_seed 2, pitch
  /// 10: seed 0 round_hill failed and east_to_west 1.256; seed 1 round_ditch unreachable). What
  /// held in every pitched run with a full turn: seed 1 round_terrace at 0 frames, and seed 0
  /// round_ditch 1.04-1.10 (NavigatePairs.PitchedLookRoundTerraceAndDitch). A half turn (3.15 rad)
  /// is worse.
  double start_look_rad = 0.0;
  /// The start look's turn rate (rad/s).
  double look_yaw_rate_rad_s = 0.6;
  /// Approach: a robot does not appear at its start, it drives there, and what its LiDAR saw on
  /// the way in is in its map. Before the first sweep at the start, the sensor sweeps from poses
  /// along the last approach_m (m) driven to the start (straight back along the start heading,
  /// one sweep every approach_sweep_m) and the sweeps are fused into the map, placed by their
  /// true poses (the robot knows where it is on arrival). The approach ends where the robot
  /// could not have come from: its footprint on a truth-impassable cell or off the scene (a
  /// start 3 m from the scene's edge has a 2.5 m approach). 0: a robot switched on where it
  /// stands, its blind disk (4.5 m for a VLP-16 at 1.2 m) unseen: a rock beside it or a pit
  /// ahead is driven into. Chosen on 48 random pairs of the terrain seeds 2-5
  /// (navigate_pairs_terrain_seed2..5.csv), none of them used before; of the 36 whose goal the
  /// truth plan reaches, with the sensor-noise seeds 1 / 2: 0 m: 35 / 36 arrived, 3 / 3 with
  /// the footprint on truth-impassable cells (664 / 32 frames), 8 / 6 longer than 1.15 x the
  /// truth plan, mean ratio 1.132 / 1.105; 2 m: 36 / 36 arrived, 0 / 0 with frames, 6 / 6 over
  /// 1.15, 1.065 / 1.073; 1 m: 35 arrived, 0 with frames, 8 over 1.15; 3 m: 36, 0, 4; 5, 7 and
  /// 9 m: 33, 31 and 33 arrived (goals called blocked once seen from another side), 0 with
  /// frames. On the seed-0 pairs 2 m takes ne_to_hill off the rock beside its start (28 -> 0
  /// frames) and round_terrace 2 -> 0; on seed 1 round_terrace goes 33 -> 39 frames (a pit's
  /// rim 2.7 m from the start, seen as flat ground), round_hill 1.148 -> 1.168 and south_east
  /// 1.038 -> 1.156. The starts on the walled-in terrace of seeds 2-5 (truth: no way off) drive
  /// off its 0.5 m step 2-4 m away whatever the length (cut there: no robot came from below).
  double approach_m = 2.0;
  double approach_sweep_m = 0.5;
  /// A robot whose pose the planner calls in collision (beside an obstacle, on its halo: the
  /// planner's footprint is inflated by its margin, the sub-cell and the heading bin; the step
  /// check's is exact) first takes the shortest straight move or R_min arc, up to escape_max_m
  /// (m), that the step check allows and that ends on a pose the planner calls free, and plans
  /// on from there (escape_path). Only when there is none are the cells within 0.3 m of the
  /// footprint cleared for the planner, which then plans through cells the step check refuses
  /// (emergency stops, re-planned the same way). 0: that clearing only.
  double escape_max_m = 1.0;
  /// A goal the map blocks while the robot is farther than blocked_goal_look_m (m) from it is
  /// not yet unreachable: seen from afar its cells hold a few returns, and the bump, step and
  /// halo rules on a few returns block ground a nearer look clears. The robot drives to the
  /// free pose nearest the goal within blocked_goal_approach_m (m) and plans again from there;
  /// the goal is unreachable when it is still blocked on two successive map updates nearer than
  /// blocked_goal_look_m (or no free pose is that near). 0: off (blocked twice from anywhere).
  /// Found on 48 random pairs of the terrain seeds 6-9 (drawn as navigate_pairs_terrain_seed2..5
  /// .csv): 29 -> 31 of the 36 reachable goals reached (two goals on flat ground 18-21 m away
  /// had been given up after 3-14 m); every pair of seeds 0-5 ends as before. 8 -> 4 m (the
  /// approach distance: a goal is judged from where the robot goes to look at it): goals on
  /// the hill's flank, 8-24 deg ground seen from below at 4-8 m, hold returns the ground
  /// segmentation does not keep as ground (obstacle evidence without ground) that a nearer
  /// look clears. Random pairs of seeds 2-21: 177 -> 180 of 184 reachable goals arrive (seeds
  /// 9 p3, 13 p9, 14 p1; 5 m: 178, 2-3 m: 180), 177 -> 179 with sensor-noise seed 2, every
  /// other outcome alike; held-out seeds 22-29 (79 reachable) and the seed 0 / 1 pairs alike.
  double blocked_goal_look_m = 4.0;
  double blocked_goal_approach_m = 4.0;
  /// Cells within the blind radius of the start pose that no sweep has seen (neither from the
  /// start nor on the approach) are planned at this tau, as known but costlier ground, rather
  /// than at the optimism of unknown cells: the first moves prefer ground the robot has seen.
  /// 0: off (unknown, at the planner's unknown_tau). Off by default: with a 2 m approach on
  /// the seed-0 pairs, at 0.3 or 0.6, round_ditch 1.185 -> 1.476 and round_terrace 1.070 / 0 ->
  /// 1.298 / 10 frames; at sensor-noise seed 3 round_terrace's 5 frames went to 0 (1.250 ->
  /// 1.222), at seed 2 no pair changed its outcome (ne_to_hill still unreachable).
  double start_disk_tau = 0.0;
  double control_period_s = 0.1;  ///< follower and motion step
  double scan_period_s = 0.5;     ///< one sweep is mapped this often (the sensor spins at 10 Hz)
  double replan_period_s = 5.0;   ///< re-plan at least this often (s)
  double replan_cost_rise = 0.1;  ///< re-plan when the rest of the path costs this share more
  /// A periodic re-plan replaces the current plan only when it costs this share less than the
  /// rest of it on the map of the moment (both costed as the planner costs a path's cells and
  /// reversing): two ways of about the same cost are not swapped back and forth. Blocked or
  /// costlier plans are re-planned as before. 0: every periodic plan is taken.
  double replan_switch_gain = 0.05;
  /// Detour hold: when the map blocks the current plan more than hold_min_ahead_m ahead and
  /// the new plan is longer than detour_hold_ratio times the rest of the current one, the robot
  /// keeps to the current plan up to hold_stop_m before the blocked pose and re-plans on every
  /// map update: the detour is taken once the block is still there that close (seen from near),
  /// or once a plan no longer than that ratio is found; a block that clears resumes the plan.
  /// A block seen from afar is often a few sparse returns that later sweeps clear (seed 0
  /// round_hill: the passage east of the hill closed at 5 m and reopened 5 s later, after the
  /// robot had turned back towards a 60 m detour). 0: off.
  double detour_hold_ratio = 1.5;
  double hold_stop_m = 1.5;
  double hold_min_ahead_m = 3.0;
  /// A plan that runs out of time or expansions is tried once more with this many times both,
  /// searched on a lattice of `retry_lattice_cell_m` cells (PlannerConfig::lattice_cell_m) when
  /// the map's are finer: a search that has to exhaust the lattice to find that no way exists
  /// (a goal walled in) grows with the number of lattice cells: on 0.25 m cells with the retry
  /// on its own lattice, 10 of the 56 truth-unreachable goals of seeds 2-21 ended `failed` (the
  /// budget spent three times) instead of reported unreachable, on a 0.5 m lattice none.
  double retry_budget_factor = 5.0;
  double retry_lattice_cell_m = 0.5;
  double goal_tolerance_m = 0.3;        ///< arrived: this close to the goal ...
  double goal_yaw_tolerance_rad = 0.3;  ///< ... and this well aligned
  double max_time_s = 0.0;              ///< 0: 40 s + 4 x the straight distance / cruise speed
  int max_safety_stops = 30;            ///< more emergency stops than this: failed
  std::uint64_t sim_seed = 1;           ///< sensor noise seed
  /// The pose the robot maps, plans, follows and stops by: the truth, or its LiDAR odometry
  /// (with the IMU and wheel streams) at every mapped sweep, carried between sweeps by the
  /// commanded speeds (navigate_poses.hpp). The truth still moves the robot and scores the run.
  PoseSource pose_source = PoseSource::kTruth;
  odometry::OdometryConfig odometry;  ///< with pose_source kOdometry
  MotionStreamsConfig streams;        ///< the IMU and wheel streams given to the odometry
  bool plan_on_truth = true;          ///< also plan on the truth map (the reference length)
};

/// One row of navigate_log.csv (one control period).
struct NavigateLogRow {
  double t_s = 0;
  double x_m = 0, y_m = 0, yaw_rad = 0;  ///< true pose at the start of the period
  double v_m_s = 0, yaw_rate_rad_s = 0;  ///< commanded
  double planned_length_m = NAN;         ///< what is left of the current plan (NaN: none)
  int cell_ix = -1, cell_iy = -1;        ///< truth cell under the robot's centre
  int cell_passable = -1;                ///< its truth: 1 passable, 0 impassable, -1 off the map
  bool footprint_on_impassable = false;  ///< the exact footprint overlaps a truth-impassable cell
  double impassable_depth_m = 0;  ///< how far into it (NavigateResult::max_impassable_depth_m)
  /// Gap between the footprint and the nearest obstacle's disc (m; negative: on it; infinite:
  /// none; NavigateResult::min_obstacle_gap_m).
  double obstacle_gap_m = INFINITY;
  double tilt_deg = 0;       ///< the chassis' tilt (NavigateResult::max_tilt_deg)
  bool tilted_over = false;  ///< tilt_deg beyond the robot's max_slope_deg
  NavigateState state = NavigateState::kPlanning;
  int replans = 0;
};

/// One plan made during the run.
struct PlanRecord {
  double t_s = 0;
  planning::Pose2 start;
  planning::PlanStatus status = planning::PlanStatus::kNoPath;
  std::string trigger;  ///< start_creep, start, creep_done, blocked, cost, period, safety_stop,
                        ///< off_goal, hold (the detour hold looking again), tilt (the tilt stop),
                        ///< look (to a viewpoint, look_at_guesses), looked (planned there)
  planning::Path path;
  double length_m = 0, search_ms = 0;
  int expansions = 0;
};

struct NavigateResult {
  NavigateOutcome outcome = NavigateOutcome::kFailed;
  std::string reason;
  planning::Pose2 start, goal;
  std::vector<NavigateLogRow> rows;
  std::vector<PlanRecord> plans;
  std::vector<planning::Pose2> driven;  ///< true poses, one per control period and the last
  double driven_length_m = 0;
  planning::PlanStatus truth_status = planning::PlanStatus::kNoPath;
  planning::Path truth_path;
  double truth_length_m = NAN;  ///< Hybrid A* on the truth map (NaN when it finds none)
  double length_ratio = NAN;    ///< driven / truth length
  std::size_t frames_on_impassable = 0;
  /// How deep a truth-impassable cell reached into the footprint, at its deepest over the drive
  /// (m, in 1 cm steps; 0 when never): the largest d for which the footprint shrunk by d on
  /// every side still overlaps such a cell. A few cm is the footprint brushing a cell whose
  /// danger (a pit's wall, a rock's base) may lie anywhere in its 0.5 m.
  double max_impassable_depth_m = 0;
  /// Control periods in which the footprint overlaps an obstacle itself (the disc of a rock,
  /// bush or trunk of the scene that the truth counts: Scene::terrain_truth), not only a cell it
  /// reaches into: a physical contact. Ground (a pit's wall, a ditch, a slope) is not an obstacle.
  std::size_t frames_on_obstacles = 0;
  /// The least gap between the footprint and those discs over the drive (m; negative: how deep
  /// one reached into the footprint; infinite when the scene has none).
  double min_obstacle_gap_m = INFINITY;
  /// The chassis' largest tilt over the drive (deg; resting on the true ground, as its IMU and
  /// the tilt stop read it): beyond the robot's max_slope_deg a wheel went down a wall or a step.
  double max_tilt_deg = 0;
  int replans = 0;  ///< plans after the first
  int safety_stops = 0;
  int tilt_stops = 0;   ///< safety stops on a tilt over NavigateConfig::tilt_stop_deg
  int guess_looks = 0;  ///< looks at guessed drops before giving up (NavigateConfig::guess_looks)
  int escapes = 0;      ///< plans that began with an escape (NavigateConfig::escape_max_m)
  /// Periodic re-plans not taken, no cheaper than NavigateConfig::replan_switch_gain asks.
  int plans_put_off = 0;
  PoseSource pose_source = PoseSource::kTruth;
  double max_pose_error_m = 0;            ///< largest distance of the robot's pose from the truth
  std::size_t odometry_unregistered = 0;  ///< sweeps the odometry kept at its motion prior
  std::size_t approach_sweeps = 0;        ///< sweeps of the approach fused before the start
  /// Where the sensor's lowest beam, level on its mast, meets level ground (m): no ground return
  /// nearer (the blind disk the map's rules stand on).
  double blind_radius_m = 0;
  std::size_t scans = 0;
  double duration_s = 0;  ///< simulated time
  double wall_s = 0;      ///< the run's wall-clock time
  double scan_ms = 0;     ///< mean wall time per mapped sweep (simulation + fusion)
  double plan_ms = 0;     ///< mean wall time per plan (map build + search)
  Grid2D built_map;       ///< planner's input at the end (traversability, impassable, points)
  Grid2D truth;           ///< Scene::terrain_truth at the map's cells
  /// built_map against truth within kMapAgreementRadiusM of the drive.
  MapAgreement map_agreement;
};

/// Throws fieldlidar::Error unless `sensor` can map the ground for the loop: a spinning
/// multi-beam LiDAR whose lowest beam points below the horizon.
void check_navigate_sensor(const SensorModel& sensor);

/// Drives from `start` to `goal` on `scene` (a terrain scene). Throws fieldlidar::Error on an
/// absurd robot, sensor or config, or a start off the scene.
NavigateResult run_navigate(const sim::Scene& scene, const SensorModel& sensor,
                            const planning::Pose2& start, const planning::Pose2& goal,
                            const NavigateConfig& config = {});

/// The rules of the planner map (area_grid) the loop rebuilds after each sweep: `config`'s
/// settings and robot, the sweep's sensor pose (map frame; its lidar_pitch_deg undone for the
/// ground the robot stands on), the robot at `robot_xy_m`, the mast's height and the sensor's
/// blind radius (m), the goal, and the sensor positions of earlier sweeps (the approach's).
AreaGridRules area_grid_rules(const NavigateConfig& config, const Pose& sensor_pose,
                              const Eigen::Vector2d& robot_xy_m, double mast_m,
                              double blind_radius_m, const Eigen::Vector2d& goal_xy_m,
                              std::span<const Eigen::Vector3d> earlier_sensors_m);

/// CSV of the log: t_s,x_m,y_m,yaw_rad,v_m_s,yaw_rate_rad_s,planned_length_m,cell_ix,cell_iy,
/// cell_passable_truth,footprint_on_impassable,state,replans
std::string navigate_log_csv(const std::vector<NavigateLogRow>& rows);

}  // namespace fieldlidar::loops
