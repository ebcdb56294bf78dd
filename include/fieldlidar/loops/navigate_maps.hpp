#pragma once
/// \file The maps of the navigate loop: the truth as the planner reads it, the fused map cut to
/// the operating area, and footprints against either.

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "fieldlidar/core/grid2d.hpp"
#include "fieldlidar/planning/planning_map.hpp"
#include "fieldlidar/planning/pose2.hpp"
#include "fieldlidar/terrain/terrain_map.hpp"
#include "fieldlidar/terrain/traversability.hpp"

namespace fieldlidar::loops {

/// The terrain truth (Scene::terrain_truth layers "passable", "slope_deg") as a planner map:
/// traversability tau = 1 - weight_slope * slope / max_slope on passable cells, 0 on the others
/// (the map's own formula without roughness, which the truth does not hold).
Grid2D truth_planning_grid(const Grid2D& truth, const terrain::TraversabilityConfig& layers);

/// What area_grid marks impassable beyond the fused map's own impassable cells.
struct AreaGridRules {
  /// A cell with at least this many returns behind it, its 8 neighbours seen too, but no
  /// traversability and no ground plane (elevation): it was seen well and holds no ground
  /// (ground too steep for the ground segmentation, such as a hill's flank, or a wall); 0 leaves
  /// such cells unknown.
  int seen_no_ground_points = 0;
  /// Around the sensor at `sensor_xy_m`, nearer than its lowest beam meets the ground (m;
  /// blind_range_m: `blind_radius_m`, mounting height / tan(-lowest elevation), for a level
  /// mount), no return can be ground: a cell there with `blind_points` returns and no ground
  /// plane (the top of a rock beside the robot at the start, which the map cannot call an
  /// obstacle without the ground under it).
  Eigen::Vector2d sensor_xy_m = Eigen::Vector2d::Zero();
  double sensor_z_m = 0.0;       ///< the sensor's height in the map's frame (m; drop bands)
  double sensor_height_m = 0.0;  ///< ... and above the ground under the robot (m)
  double blind_radius_m = 0.0;
  int blind_points = 3;
  /// A likely negative obstacle (layer kNegativeObstacle: a trench shadow not seen yet), but
  /// within `goal_clear_m` (m) of `goal_xy_m`: a guess from a shadow never makes a goal
  /// unreachable; the robot goes to look, and a real ditch there is blocked by the map once seen.
  bool negative_impassable = false;
  Eigen::Vector2d goal_xy_m = Eigen::Vector2d::Zero();
  double goal_clear_m = 0.0;
  /// Drop-offs seen from above (see mark_drop_bands): cells without a return on a line between
  /// two ground cells no more than drop_band_max_m apart whose heights differ by more than
  /// drop_min_m and by a slope steeper than drop_min_slope_deg, found between blind_radius_m and
  /// drop_radius_m from the sensor (m); a band of 0 m: off. Not within goal_clear_m of the goal.
  double drop_band_max_m = 0.0;
  double drop_min_m = 0.0;
  double drop_min_slope_deg = 0.0;
  double drop_ray_share = 0.5;
  double drop_rise_per_m = 0.03;
  double drop_radius_m = 0.0;
  /// Drops hidden in the blind disk (see mark_blind_drops): rays from blind_drop_clear_m (m; the
  /// footprint's reach; 0: off) out to blind_drop_reach_m (m) beyond the blind radius, the ground
  /// plane the robot stands on (its normal in the map frame), the ground's slope measured over
  /// blind_drop_slope_run_m (m) beyond the first ground cell, clamped to max_slope_deg.
  double blind_drop_clear_m = 0.0;
  double blind_drop_reach_m = 3.0;
  double blind_drop_slope_run_m = 1.0;
  Eigen::Vector3d ground_normal = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d sensor_up = Eigen::Vector3d::UnitZ();  ///< the sensor's z axis, map frame
  double blind_drop_shadow_tolerance_m = 0.75;
  double max_slope_deg = 25.0;
  /// Where the sensor stood for earlier sweeps in the map (m; the approach's): the lower ground
  /// may be the shadow's end as one of them saw it, nearer than the robot's own lowest beam.
  std::span<const Eigen::Vector3d> earlier_sensors_m;
  /// Cells the robot has driven over (non-zero; empty: none known): no drop mark stands there.
  std::span<const std::uint8_t> driven;
};

/// How far from the sensor, in the map direction `u` (unit), its lowest beam meets the ground
/// plane the robot stands on (m): nearer, no return there can be ground. rules.blind_radius_m
/// for a level mount (its lowest beam rules.sensor_height_m over rules.blind_radius_m); a mount
/// tilted on the robot (rules.sensor_up against rules.ground_normal) sees the ground nearer on
/// the side it leans to and farther on the other; infinite where the beam does not descend.
double blind_range_m(const AreaGridRules& rules, const Eigen::Vector2d& u);

/// The fused map's traversability, impassable and points layers on `area` (cells the fused map has
/// not seen stay unknown: NaN tau, 0 points), with the cells `rules` name impassable too.
Grid2D area_grid(const terrain::TerrainMap& map, const GridGeometry& area,
                 const AreaGridRules& rules = {});

/// The same, with the drop bands' marks (mark_drop_bands) kept in `drop_marks` between calls
/// (resized to the area when it is not its size): marked cells are impassable but within
/// rules.goal_clear_m of the goal (a guess never makes a goal unreachable).
Grid2D area_grid(const terrain::TerrainMap& map, const GridGeometry& area,
                 const AreaGridRules& rules, std::vector<std::uint8_t>& drop_marks);

/// The foot of a step down (a terrace's edge, a bank, a wall's top) lies in the shadow of its lip
/// and is never seen from above, not even from the lip, which is inside the sensor's blind disk
/// by then: the map holds ground, a band of cells without a return, then ground lower by more
/// than the robot's step. Such a band is marked in `marks` (one byte per cell of `area`, kept
/// between calls): a cell without a return (`points` 0) and without ground (`elevation` NaN),
/// between rules.blind_radius_m and rules.drop_radius_m from rules.sensor_xy_m, on one of the
/// four lines through it (the axes, the diagonals) within 30 deg of the sensor's ray, between
/// ground cells at most rules.drop_band_max_m apart (centre to centre) whose elevations differ
/// by more than rules.drop_min_m and by a slope steeper than rules.drop_min_slope_deg, where
/// - the higher is nearer the sensor (a face turned to it shows gaps between rings, no shadow);
/// - the higher is not `blocked` (a rock's top kept as ground: behind it is its own shadow);
/// - the higher is at most drop_min_m, plus drop_rise_per_m per metre from the sensor (gentle
///   ground rising to the lip), above the ground under the robot (rules.sensor_z_m -
///   rules.sensor_height_m): an edge the robot stands above, not the far side of a bank or
///   terrace seen from below, which it cannot drive off;
/// - the straight line between them is steeper than rules.drop_ray_share of the sensor's ray to
///   the higher: ground that gentle would have shown, so the band is a shadow, not a gap between
///   two rings on a downslope (a step's shadow ends where the ray over its lip meets the lower
///   ground, so the line is about as steep as that ray, less the ground seen short of the lip).
/// A mark stays until the cell is seen (a return or ground in it); inside the blind disk nothing
/// is marked (unseen there for want of a beam, not for a shadow). A ditch (both lips level), the
/// shadow behind a rock (the ground beyond level with the ground before) and the gaps between
/// rings on gentle ground are not drops.
void mark_drop_bands(const GridGeometry& area, std::span<const float> elevation,
                     std::span<const float> points, std::span<const std::uint8_t> blocked,
                     const AreaGridRules& rules, std::span<std::uint8_t> marks);

/// The marks mark_drop_bands and mark_blind_drops leave: a drop band (a shadow behind a lip,
/// which no pose on the lip's side can see into) and a blind drop (unseen for the blind disk
/// alone: seen from farther it is seen); a blind drop's cell later found in a band is a band.
constexpr std::uint8_t kDropBandMark = 1, kBlindDropMark = 2;

/// A step down beside a robot that has not moved far enough to see it: the blind disk
/// (rules.blind_radius_m) hides the lip and the shadow below it, and the near side that
/// mark_drop_bands needs is the ground the robot stands on. Along rays from rules.sensor_xy_m,
/// from rules.blind_drop_clear_m out to rules.blind_drop_reach_m beyond the blind radius, the
/// cells without a return or ground (`points` 0, `elevation` NaN) up to the first ground cell are
/// marked in `marks` when that ground
/// - is where the sensor's lowest beam (rules.sensor_height_m / rules.blind_radius_m, tilted
///   with rules.sensor_up) meets it, not nearer by more than blind_drop_shadow_tolerance_m, from
///   here or from one of rules.earlier_sensors_m behind the robot within 30 deg of the ray
///   (ground seen nearer than any of them could is no shadow's end: a hollow seen from aside);
/// - lies more than rules.drop_min_m, plus drop_rise_per_m per metre, below the plane the robot
///   stands on (rules.sensor_z_m - rules.sensor_height_m, normal rules.ground_normal) carried
///   out to it, and
/// - followed back to the robot along its own slope (measured over blind_drop_slope_run_m beyond
///   it, clamped to max_slope_deg) passes more than drop_min_m below the robot's ground: ground
///   falling away past a crest leads back up to the robot, the foot of a terrace's edge does not.
/// A ray meeting a return that is not ground (a rock, a wall) marks nothing. Marks stay until
/// the cell is seen (mark_drop_bands clears them).
void mark_blind_drops(const GridGeometry& area, std::span<const float> elevation,
                      std::span<const float> points, const AreaGridRules& rules,
                      std::span<std::uint8_t> marks);

/// Cells never seen (no return) between inner_m and outer_m from the sensor are shadows: ground
/// the sensor would have seen were it not hidden (behind a rock, inside a ditch or pit). They get
/// tau `shadow_tau` (known, costlier) instead of the optimism of unknown cells, so plans near the
/// robot prefer ground it has seen; cells farther away stay unknown.
void cost_shadows(Grid2D& grid, const Eigen::Vector2d& sensor_xy_m, double inner_m, double outer_m,
                  float shadow_tau);

/// Known-impassable cells of a planner grid (impassable flag, or known tau <= 0).
std::vector<std::uint8_t> known_blocked(const Grid2D& grid);

/// Linear indices of the cells the robot's exact rectangle (half sizes, m) at `pose` overlaps;
/// -1 for a part off the grid.
std::vector<long> footprint_cells(const GridGeometry& geometry, const planning::Pose2& pose,
                                  const terrain::RobotConfig& robot);

/// Sets `driven` (resized to the geometry's cells) on the cells whose centres lie within the
/// robot's exact rectangle at `pose`: ground it stands on.
void mark_driven(const GridGeometry& geometry, const planning::Pose2& pose,
                 const terrain::RobotConfig& robot, std::vector<std::uint8_t>& driven);

/// The free pose (PlanningMap::pose_free) nearest `goal` within `tolerance_m` of it, same
/// heading: rings of 0.05 m steps, 16 directions each; nullopt when there is none.
std::optional<planning::Pose2> nearest_free_pose(const planning::PlanningMap& map,
                                                 const planning::Pose2& goal, double tolerance_m);

/// A straight path of `length_m` from `start` along its heading (backwards when `reverse`), one
/// sample every `step_m`.
planning::Path straight_path(const planning::Pose2& start, double length_m, bool reverse,
                             double step_m = 0.1);

/// The step check of the navigate loop: the exact footprint at `next` enters a cell that
/// `blocked` (known_blocked on `area`) marks, or leaves the grid, other than the cells in
/// `standing` (footprint_cells of the pose the robot stands on: it may stay where it is).
bool footprint_enters_blocked(const GridGeometry& area, const std::vector<std::uint8_t>& blocked,
                              const std::vector<long>& standing, const planning::Pose2& next,
                              const terrain::RobotConfig& robot);

/// The way out of a pose `from` that `map` does not call free (its footprint mask, inflated by
/// the margin, the sub-cell and the heading bin, touches a blocked cell: the robot stands beside
/// an obstacle or on its halo): the shortest straight move or arc at the robot's R_min (straight
/// first, towards the goal's side first: backwards when `goal_behind`), in steps of `step_m` up
/// to `max_m`, every pose of which passes the step check (footprint_enters_blocked against
/// `blocked`, standing at `from`) and whose last pose `map` calls free. Starts with `from`;
/// nullopt when there is none.
std::optional<planning::Path> escape_path(const planning::PlanningMap& map,
                                          const std::vector<std::uint8_t>& blocked,
                                          const planning::Pose2& from, bool goal_behind,
                                          double max_m, double step_m = 0.05);

/// Marks the cells under the robot at `pose` (its rectangle grown by `grow_m`) as known passable
/// at tau >= 0.5: the robot stands there, so the planner may start there.
void clear_under_robot(Grid2D& grid, const planning::Pose2& pose, const terrain::RobotConfig& robot,
                       double grow_m);

/// The built map against the truth on the cells within `radius_m` of a drive (cells whose centre
/// lies that near one of its poses): how far the map the robot planned on was right where it
/// mattered. A cell is known to the map when it is impassable, or has a traversability and
/// returns behind it.
struct MapAgreement {
  double radius_m = 0;
  std::size_t known_cells = 0;     ///< cells the built map knows near the drive
  std::size_t truth_passable = 0;  ///< of them, passable in the truth
  /// Truth-passable cells the map blocks (obstacles read wider than they are: a lost way, a
  /// longer drive), and of those, the ones next to a truth-impassable cell (8 neighbours).
  std::size_t passable_blocked = 0;
  std::size_t passable_blocked_beside_impassable = 0;
  /// Truth-impassable cells the map calls passable (a danger it missed).
  std::size_t impassable_passable = 0;
};

/// The navigate loop's radius for MapAgreement (m): the ground the robot planned its moves on
/// (a plan's next seconds and the cells beside it that decide a way round).
inline constexpr double kMapAgreementRadiusM = 3.0;

/// MapAgreement of `built` (layers traversability, impassable and optionally points) against
/// `truth` (layer "passable", Scene::terrain_truth) on the same cells. Throws fieldlidar::Error
/// when the grids differ or a layer is missing.
MapAgreement map_agreement(const Grid2D& built, const Grid2D& truth,
                           std::span<const planning::Pose2> driven, double radius_m);

}  // namespace fieldlidar::loops
