/// Overhangs the ground segmentation took for ground: returns standing more than the robot's
/// clearance (plus the rise of climbable ground over 3 x 3 cells) above the lowest ground near
/// them, this scan's or the fused map's, are no ground.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "fused_cell.hpp"

namespace fieldlidar::terrain::detail {

std::vector<std::uint8_t> drop_overhang_ground(std::span<const Eigen::Vector3d> pts,
                                               std::span<const std::uint8_t> is_ground,
                                               std::span<const Eigen::Vector2i> cells_of,
                                               const Eigen::Vector2i& lo, int w, int h,
                                               CellStore& store, const FusionConfig& config) {
  std::vector<std::uint8_t> out(is_ground.begin(), is_ground.end());
  const double cm = config.layers.cell_m;
  // The clearance, plus the most that ground the robot can climb rises across 3 x 3 cells.
  const double kDeg = std::numbers::pi / 180.0;
  const double rise =
      config.layers.robot.clearance_m +
      2.0 * std::sqrt(2.0) * cm * std::tan(config.layers.robot.max_slope_deg * kDeg);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  // Cells of the scan's window padded by one (the neighbours of its edge cells).
  const Eigen::Vector2i origin = lo - Eigen::Vector2i(1, 1);
  const int pw = w + 2, ph = h + 2;
  const auto index = [&](std::size_t i) {
    return std::size_t(cells_of[i].y() - origin.y()) * pw +
           std::size_t(cells_of[i].x() - origin.x());
  };
  // This scan's lowest ground return per cell.
  std::vector<float> lowest(std::size_t(pw) * ph, std::numeric_limits<float>::infinity());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (!out[i] || !pts[i].allFinite()) continue;
    float& z = lowest[index(i)];
    z = std::min(z, float(pts[i].z()));
  }
  // A cell whose highest fused ground return stands more than the clearance above this scan's
  // ground in it held an overhang seen before any ground near it: its ground statistics start
  // again (this scan's returns there are judged against this scan's ground). Judged by the mean
  // ground, a cell that had both (a branch seen from afar in one scan, the ground beside it in
  // another) kept the branch: terrain seed 17, cells under a branch with steps of 1.0-1.2 m; and
  // a cell of one or two such returns was not judged at all (seed 13: step 0.41 m).
  const CellBlock cells(store, origin, pw, ph);
  const auto start_again = [](FusedCell& cell) {
    cell.ground = PlaneSums{};
    cell.z_ref = std::numeric_limits<float>::quiet_NaN();
    cell.ground_top.fill(-std::numeric_limits<float>::infinity());
    cell.ground_max = -std::numeric_limits<float>::infinity();
    cell.ground_min = std::numeric_limits<float>::infinity();
    cell.mean.setZero();
    cell.covariance.setZero();
    cell.own_normal_fresh = false;
  };
  for (int y = 1; y <= h; ++y)
    for (int x = 1; x <= w; ++x) {
      const float z = lowest[std::size_t(y) * pw + x];
      FusedCell* cell = std::isfinite(z) ? cells.find(origin.x() + x, origin.y() + y) : nullptr;
      if (cell && cell->ground.n > 0 && double(cell->ground_max) + cell->z_ref > z + rise)
        start_again(*cell);
    }
  // The lowest ground of each cell, this scan's or the map's, then of the 3 x 3 cells around it
  // (each worked out when first asked for: most cells of the window hold none).
  constexpr double kUnset = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> low(std::size_t(pw) * ph, kUnset), low3(std::size_t(pw) * ph, kUnset);
  const auto low_of = [&](int x, int y) {
    double& v = low[std::size_t(y) * pw + x];
    if (std::isnan(v)) {
      v = double(lowest[std::size_t(y) * pw + x]);
      const FusedCell* q = cells.find(origin.x() + x, origin.y() + y);
      if (q && q->ground.n >= config.min_ground_points)
        v = std::min(v, double(q->ground_min) + double(q->z_ref));
    }
    return v;
  };
  // A cell whose lowest fused ground return stands more than the clearance above the ground of a
  // cell next to it (this scan's, or the map's lowest) holds nothing but an overhang, the ground
  // under it unseen since (seed 17: a branch seen from 23-25 m, 2.6 m above the ground the
  // robot saw beside it later, blocked the goal's cells): it starts again.
  std::vector<FusedCell*> lifted;
  for (int y = 1; y <= h; ++y)
    for (int x = 1; x <= w; ++x) {
      FusedCell* cell = cells.find(origin.x() + x, origin.y() + y);
      if (!cell || cell->ground.n <= 0) continue;
      double beside = kInf;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          if (dx != 0 || dy != 0) beside = std::min(beside, low_of(x + dx, y + dy));
      if (double(cell->ground_min) + cell->z_ref > beside + rise) lifted.push_back(cell);
    }
  for (FusedCell* cell : lifted) start_again(*cell);
  if (!lifted.empty()) std::fill(low.begin(), low.end(), kUnset);  // their lows have changed
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (!out[i] || !pts[i].allFinite()) continue;
    const int x = cells_of[i].x() - origin.x(), y = cells_of[i].y() - origin.y();
    double& m = low3[std::size_t(y) * pw + x];
    if (std::isnan(m)) {
      m = kInf;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) m = std::min(m, low_of(x + dx, y + dy));
    }
    if (pts[i].z() > m + rise) out[i] = 0;
  }
  return out;
}

}  // namespace fieldlidar::terrain::detail
