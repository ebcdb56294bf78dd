/// Overhangs the ground segmentation took for ground: returns standing more than the robot's
/// clearance (plus the rise of climbable ground over 3 x 3 cells) above the lowest ground near
/// them, this scan's or the fused map's, are no ground.
#include <cmath>
#include <limits>
#include <unordered_map>

#include "fused_cell.hpp"

namespace fieldlidar::terrain::detail {
namespace {

std::int64_t cell_key(int ix, int iy) {
  return (std::int64_t(ix) << 32) ^ std::int64_t(std::uint32_t(iy));
}

}  // namespace

std::vector<std::uint8_t> drop_overhang_ground(std::span<const Eigen::Vector3d> pts,
                                               std::span<const std::uint8_t> is_ground,
                                               CellStore& store, const FusionConfig& config) {
  std::vector<std::uint8_t> out(is_ground.begin(), is_ground.end());
  const double cm = config.layers.cell_m;
  // The clearance, plus the most that ground the robot can climb rises across 3 x 3 cells.
  const double kDeg = 3.14159265358979323846 / 180.0;
  const double rise =
      config.layers.robot.clearance_m +
      2.0 * std::sqrt(2.0) * cm * std::tan(config.layers.robot.max_slope_deg * kDeg);
  const auto cell_of = [cm](double v) { return int(std::floor(v / cm)); };
  // This scan's lowest ground return per cell.
  std::unordered_map<std::int64_t, float> lowest;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (!out[i] || !pts[i].allFinite()) continue;
    auto [it, fresh] =
        lowest.try_emplace(cell_key(cell_of(pts[i].x()), cell_of(pts[i].y())), float(pts[i].z()));
    if (!fresh) it->second = std::min(it->second, float(pts[i].z()));
  }
  // A cell whose fused ground stands more than the clearance above this scan's ground in it held
  // an overhang seen before any ground near it: its ground statistics start again.
  for (const auto& [key, z] : lowest) {
    FusedCell* cell = store.find(int(key >> 32), int(std::int32_t(std::uint32_t(key))));
    if (!cell || cell->ground.n < config.min_ground_points) continue;
    if (cell->mean.z() + cell->z_ref <= z + rise) continue;
    cell->ground = PlaneSums{};
    cell->z_ref = std::numeric_limits<float>::quiet_NaN();
    cell->ground_top.fill(-std::numeric_limits<float>::infinity());
    cell->mean.setZero();
    cell->covariance.setZero();
  }
  // The lowest ground of the 3 x 3 cells around each ground return, from this scan and the map.
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (!out[i] || !pts[i].allFinite()) continue;
    const int ix = cell_of(pts[i].x()), iy = cell_of(pts[i].y());
    double low = std::numeric_limits<double>::infinity();
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        if (auto it = lowest.find(cell_key(ix + dx, iy + dy)); it != lowest.end())
          low = std::min(low, double(it->second));
        const FusedCell* q = store.find(ix + dx, iy + dy);
        if (q && q->ground.n >= config.min_ground_points)
          low = std::min(low, q->mean.z() + double(q->z_ref));
      }
    if (pts[i].z() > low + rise) out[i] = 0;
  }
  return out;
}

}  // namespace fieldlidar::terrain::detail
