#pragma once
// The steps of the robust ground segmentation (ground_robust) and the per-cell state they pass
// on: the plane fit of each polar cell, its growth outward from the sensor, the agreement with
// the neighbouring cells, the labelling of the points and the two rejection tests after it.
// Internal to segmentation/.

#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "fieldlidar/segmentation/ground.hpp"
#include "ground_plane.hpp"
#include "polar_grid.hpp"

namespace fieldlidar::segmentation::detail {

enum class CellState : std::uint8_t { kEmpty, kGround, kRejected };

// What the passes after the fit need of a cell, kept small: the cells of a frame are swept
// several times.
struct CellFit {
  float elevation = 0.f;               ///< m, plane height at the cell's centre
  float predicted = 0.f;               ///< m, ground height expected from the inner cells
  float gx = 0.f, gy = 0.f, g0 = 0.f;  ///< plane as z = -(gx x + gy y + g0)
  CellState state = CellState::kEmpty;

  /// Height of (x, y, z) above the cell's ground plane, along z (m).
  template <class P>
  float height_above(const P& p) const {
    return gx * p.x + gy * p.y + p.z + g0;
  }
  /// Height above the cell's ground: its plane in a ground cell, else the ground expected from
  /// the neighbouring cells (m).
  template <class P>
  float height_over_ground(const P& p) const {
    return state == CellState::kGround ? height_above(p) : p.z - predicted;
  }
};

// The fit's own tests, used once.
struct PlaneFit {
  Eigen::Vector3f normal{0.f, 0.f, 1.f};  ///< up-pointing unit normal of the low points
  float flatness = 0.f;                   ///< m, sqrt of the smallest eigenvalue
  bool upright = true;
  /// The low points lie along one scan line: the plane's tilt is unknown (kept horizontal).
  bool line_only = false;
};

// A line-only cell's low points (within `band` of z): their mean horizontal range (m), and
// whether nothing in the cell lies above them.
struct LineStats {
  float rho = 0.f;
  bool alone = false;
};

/// The line statistics of a cell's points `members`, whose horizontal ranges are rho[0..] (m).
LineStats line_stats(std::span<const CellPoint> members, const float* rho, float band);

/// PCA of the cell's low points (within seed_band_m of its lowest return z_min); the plane goes
/// into `fit` (elevation at the cell's centre (cx, cy), gradients), its tests are returned.
PlaneFit fit_cell(std::span<const CellPoint> members, float z_min, double seed_band_m,
                  float max_cos, float cx, float cy, CellFit& fit);

/// Radial length of the polar cells at range r_m (m).
inline double cell_length_m(const RobustGroundConfig& config, double r_m) {
  return std::max(config.min_cell_m, config.cell_growth * r_m);
}

/// How far above the prior plane a sector's first cell at `range_m` may stand and still continue
/// the ground (RobustGroundConfig::first_cell_max_rise_m): the cap times min(1, (range_m /
/// blind_radius_m)^2); 0 without a downward beam (`blind_radius_m` infinite).
double first_cell_rise_m(const RobustGroundConfig& config, double range_m, double blind_radius_m);

/// Pass 1, per sector from the sensor outward: a cell is ground when its low-point plane is
/// upright and flat and continues the ground of the inner cells (or, before any, the `prior`
/// plane). `sparse_rings`: a beam table of 32 rings or fewer; `blind_radius_m`: where the
/// lowest beam meets level ground (m).
std::vector<CellFit> grow_ground_cells(const PolarGrid& grid, const PolarCells& cells,
                                       const NearGroundPlane& prior,
                                       const RobustGroundConfig& config, bool sparse_rings,
                                       double blind_radius_m);

/// Pass 2: agreement with the neighbouring cells across sectors.
void agree_with_neighbours(const PolarGrid& grid, const RobustGroundConfig& config,
                           std::vector<CellFit>& fits);

/// The points of each non-empty cell near its ground become ground in `result`.
void label_ground_points(const PolarCells& cells, const std::vector<CellFit>& fits,
                         const RobustGroundConfig& config, bool sparse_rings, GroundResult& result);

/// Rejects the ground returns at the foot of a vertical face, on azimuth columns of `columns`
/// (image columns of `rings` rings with a ring field; rings = 0 without one).
void reject_face_feet(const PolarGrid& grid, const PolarCells& cells,
                      const RobustGroundConfig& config, int columns, int rings,
                      GroundResult& result);

/// Rejects the ground returns under low vegetation (dense beam tables).
void reject_under_vegetation(const PolarGrid& grid, const PolarCells& cells,
                             const std::vector<CellFit>& fits, const RobustGroundConfig& config,
                             GroundResult& result);

}  // namespace fieldlidar::segmentation::detail
