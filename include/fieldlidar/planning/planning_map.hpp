#pragma once
/// \file The traversability map as the planner sees it: per-cell tau and blocked flags, the
/// robot's oriented-rectangle footprint as precomputed cell offsets, and a distance field.

#include <cmath>
#include <cstdint>
#include <vector>

#include "fieldlidar/core/grid2d.hpp"
#include "fieldlidar/planning/pose2.hpp"
#include "fieldlidar/terrain/traversability.hpp"

namespace fieldlidar::planning {

/// How map cells are read.
struct MapReadConfig {
  /// Cells whose tau is unknown (NaN, or no return behind them) are driven over at this tau when
  /// allowed (the robot learns them as it comes close); blocked otherwise.
  bool allow_unknown = true;
  double unknown_tau = 0.5;
  /// Extra clearance (m) added on every side of the robot's rectangle.
  double footprint_margin_m = 0.05;
};

/// How a cell of a traversability map reads: impassable when its layer says so (seen or not),
/// unknown without a traversability or without a return behind it, else blocked at tau <= 0 (seed
/// 004, f31: tau = 0 is not driven on) or passable. Without an impassable layer pass 0, without a
/// points layer 1.
enum class CellRead { kUnknown, kBlocked, kPassable };
inline CellRead read_cell(float tau, float impassable, float points) {
  if (impassable > 0.5f) return CellRead::kBlocked;
  if (!std::isfinite(tau) || !(points > 0.0f)) return CellRead::kUnknown;
  return tau <= 0.0f ? CellRead::kBlocked : CellRead::kPassable;
}

/// Footprint masks: one per heading bin and per position of the centre within its cell
/// (kSubcells x kSubcells). Each holds the cells that the rectangle (inflated by the margin, by
/// the half-diagonal of a sub-cell and by the rotation over half a heading bin) overlaps, so a
/// pose whose mask is free has its exact footprint free.
inline constexpr int kSubcells = 8;
inline constexpr int kFootprintHeadingBins = 72;
/// The most cells the footprint's diagonal (with the margin) may span: finer maps are refused.
inline constexpr int kMaxFootprintCells = 64;

class PlanningMap {
 public:
  /// Reads layer kTraversability (required; tau in [0, 1], NaN unknown) and, when present,
  /// kImpassable and kPoints of `map`. Throws fieldlidar::Error naming the field when the layer is
  /// missing, the grid is empty, the robot is absurd (sides not in (0, 20] m) or the cells so
  /// small that its footprint spans more than kMaxFootprintCells.
  PlanningMap(const Grid2D& map, const terrain::RobotConfig& robot, const MapReadConfig& config);

  const GridGeometry& geometry() const { return geometry_; }
  const terrain::RobotConfig& robot() const { return robot_; }
  const MapReadConfig& config() const { return config_; }
  std::size_t known_cells() const { return known_cells_; }

  bool blocked(std::size_t i) const { return blocked_[i] != 0; }
  /// tau used for the cost (unknown_tau on unknown cells).
  float tau(std::size_t i) const { return tau_[i]; }
  bool known(std::size_t i) const { return known_[i] != 0; }
  /// Linear index of the cell holding a point, -1 off the map.
  long cell_index(double x_m, double y_m) const;

  /// True when the robot's (inflated) footprint at `pose` lies on the map on unblocked cells.
  bool pose_free(const Pose2& pose) const;
  /// The exact rectangle (plus `margin_m`) at `pose` overlaps a blocked or off-map cell.
  bool footprint_hits_blocked(const Pose2& pose, double margin_m) const;
  /// Distance (m) from a cell centre to the nearest blocked cell centre (large where none).
  float obstacle_distance_m(std::size_t i) const { return distance_m_[i]; }
  /// Bilinear distance to obstacles at a point (m).
  double obstacle_distance_at(double x_m, double y_m) const;

 private:
  struct Offset {
    std::int16_t dx, dy;
  };
  void build_masks();
  void build_distance_field();

  GridGeometry geometry_;
  terrain::RobotConfig robot_;
  MapReadConfig config_;
  std::vector<float> tau_;
  std::vector<std::uint8_t> blocked_, known_;
  std::vector<float> distance_m_;
  std::size_t known_cells_ = 0;
  std::vector<std::vector<Offset>> masks_;  ///< [(bin * kSubcells + sy) * kSubcells + sx]
  /// The same cells as offsets of the linear index (for poses whose mask lies on the map)
  std::vector<std::vector<std::int32_t>> linear_masks_;
  int reach_cells_ = 0;  ///< largest |dx|, |dy| of any mask
};

/// Cells of `geometry` that the oriented rectangle (half sizes, m) at `pose` overlaps (separating
/// axes), as linear indices; cells off the map are returned as -1.
std::vector<long> rectangle_cells(const GridGeometry& geometry, const Pose2& pose,
                                  double half_length_m, double half_width_m);

}  // namespace fieldlidar::planning
