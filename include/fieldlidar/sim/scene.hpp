#pragma once
/// \file A simulated world: static geometry (a triangle mesh with labels over a height field),
/// walking people, and the ground truth each pipeline is checked against.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "fieldlidar/core/grid2d.hpp"
#include "fieldlidar/core/labels.hpp"
#include "fieldlidar/sim/heightfield.hpp"
#include "fieldlidar/sim/mesh.hpp"
#include "fieldlidar/sim/walker.hpp"

namespace fieldlidar::sim {

enum class SceneKind { kLawn, kGreenhouse, kForest, kTerrain, kCustom };
std::string to_string(SceneKind kind);
/// "lawn", "greenhouse", "forest", "terrain"; nullopt otherwise.
std::optional<SceneKind> scene_kind_from_string(const std::string& name);

/// One tree of a forest scene. Trunk points carry make_label(kTrunk, id).
struct TreeTruth {
  std::uint16_t id = 0;
  Eigen::Vector3d base_m = Eigen::Vector3d::Zero();  ///< axis point at ground level (world)
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();   ///< unit vector up the (main) trunk
  double dbh_m = 0.3;      ///< diameter at breast height (1.3 m along the axis)
  double height_m = 15.0;  ///< length of the main trunk
  bool leaning = false;    ///< axis more than 5 deg from vertical
  bool forked = false;     ///< splits into two stems (fork_height_m above the base)
  double fork_height_m = 0.0;
  int low_branches = 0;        ///< branches below 3 m
  double taper_m_per_m = 0.0;  ///< radius decrease per metre along the axis

  /// Trunk radius (m) at `along_m` metres along the axis from the base.
  double radius_at(double along_m) const { return dbh_m / 2 - taper_m_per_m * (along_m - 1.3); }
};

/// Something on the ground (rock, bush) or above it (overhanging branch) that the terrain truth
/// accounts for: a vertical cylinder footprint between bottom and top heights above the ground.
struct ObstacleTruth {
  Eigen::Vector2d center_m = Eigen::Vector2d::Zero();
  double radius_m = 0.5;
  double bottom_above_ground_m = 0.0;
  double top_above_ground_m = 0.5;
  LabelClass label = LabelClass::kObstacle;
  /// Blocks a robot of this clearance that drives over objects lower than min_height_m: it
  /// reaches from below the clearance to above that height.
  bool blocks(double clearance_m, double min_height_m) const {
    return bottom_above_ground_m < clearance_m && top_above_ground_m > min_height_m &&
           top_above_ground_m > bottom_above_ground_m;
  }
};

/// How the terrain truth judges a cell: a robot with this clearance and slope/step limits.
struct TerrainTruthConfig {
  double resolution_m = 0.5;
  double max_slope_deg = 25.0;          ///< steeper ground is impassable
  double max_step_m = 0.2;              ///< larger height jumps within a cell (+ neighbours) block
  double robot_clearance_m = 1.2;       ///< objects higher than this above ground are overhangs
  double min_obstacle_height_m = 0.15;  ///< objects lower than this are driven over
};

class Scene {
 public:
  Scene() = default;
  Scene(SceneKind kind, HeightField ground, std::uint64_t seed = 0);

  SceneKind kind() const { return kind_; }
  std::uint64_t seed() const { return seed_; }

  // --- static geometry
  const HeightField& ground() const { return ground_; }
  /// World z of the terrain under xy (m).
  double ground_height_at(const Eigen::Vector2d& xy_m) const { return ground_.height_at(xy_m); }
  /// All static triangles, the ground included (ground triangles labelled kGround).
  const TriangleMesh& mesh() const { return mesh_; }
  void add_mesh(const TriangleMesh& mesh) { mesh_.append(mesh); }
  /// World x-y rectangle of the scene.
  Eigen::Vector2d min_m() const { return ground_.min_m(); }
  Eigen::Vector2d max_m() const { return ground_.max_m(); }

  // --- people
  void add_walker(Walker walker) { walkers_.push_back(std::move(walker)); }
  const std::vector<Walker>& walkers() const { return walkers_; }
  /// Every person's truth at time t (world frame, x-y on the ground).
  std::vector<PersonTruth> people_at(double t_s) const;
  std::vector<PersonBody> bodies_at(double t_s) const;

  // --- truth
  /// Lawn: the operator's closed polyline (walker 1's path); empty for other scenes.
  const std::vector<Eigen::Vector2d>& operator_path() const { return operator_path_; }
  void set_operator_path(std::vector<Eigen::Vector2d> path) { operator_path_ = std::move(path); }
  /// Forest: one entry per tree (id = label instance of its trunk points).
  const std::vector<TreeTruth>& trunks() const { return trees_; }
  void add_tree(const TreeTruth& tree) { trees_.push_back(tree); }
  const std::vector<ObstacleTruth>& obstacles() const { return obstacles_; }
  void add_obstacle(const ObstacleTruth& o) { obstacles_.push_back(o); }
  /// Terrain truth on a grid of the given resolution covering the scene. Layers: "elevation" (m,
  /// at the cell centre), "slope_deg" (steepest ground within the cell), "step_m" (height range
  /// over the cell and its 8 neighbours beyond what max_slope_deg explains over 3 cells),
  /// "obstacle" (1 = an ObstacleTruth reaching into [min_obstacle_height, clearance]),
  /// "passable" (1 when slope, step and obstacle are all within the limits, else 0).
  Grid2D terrain_truth(const TerrainTruthConfig& config = {}) const;

  // --- the robot
  /// Waypoints (world x-y, m) of the scene's scripted robot route.
  const std::vector<Eigen::Vector2d>& robot_route() const { return robot_route_; }
  void set_robot_route(std::vector<Eigen::Vector2d> route, bool closed) {
    robot_route_ = std::move(route);
    robot_route_closed_ = closed;
  }
  bool robot_route_closed() const { return robot_route_closed_; }
  /// Height of the sensor above the ground on this scene's robot (m).
  double sensor_height_m() const { return sensor_height_m_; }
  void set_sensor_height_m(double h) { sensor_height_m_ = h; }
  /// Suggested cruise speed of the robot (m/s).
  double robot_speed_m_s() const { return robot_speed_m_s_; }
  void set_robot_speed_m_s(double v) { robot_speed_m_s_ = v; }

 private:
  SceneKind kind_ = SceneKind::kCustom;
  std::uint64_t seed_ = 0;
  HeightField ground_;
  TriangleMesh mesh_;
  std::vector<Walker> walkers_;
  std::vector<Eigen::Vector2d> operator_path_;
  std::vector<TreeTruth> trees_;
  std::vector<ObstacleTruth> obstacles_;
  std::vector<Eigen::Vector2d> robot_route_;
  bool robot_route_closed_ = false;
  double sensor_height_m_ = 0.5;
  double robot_speed_m_s_ = 1.0;
};

}  // namespace fieldlidar::sim
