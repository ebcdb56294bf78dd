/// See-through evidence: the rays of a scan walked cell by cell (2D DDA) from the sensor to their
/// returns; a cell holding obstacle evidence that a ray crosses inside the obstacle's height band
/// and leaves is free there in this scan.
#include <cmath>
#include <cstdint>
#include <vector>

#include "fused_cell.hpp"

namespace fieldlidar::terrain::detail {

void mark_seen_through(std::span<ScanCell> local, const Eigen::Vector2i& lo, int w, int h,
                       std::span<const Eigen::Vector3d> pts, const Eigen::Vector3d& sensor_m,
                       int stride, const FusionConfig& config) {
  const double cm = config.layers.cell_m;
  const double min_h = config.layers.robot.min_obstacle_height_m;
  const double clearance = config.layers.robot.clearance_m;
  const double margin = 0.05;  // m below the recorded top: grazing the top is no see-through
  const int sx = int(std::floor(sensor_m.x() / cm)), sy = int(std::floor(sensor_m.y() / cm));
  // The cells a ray can see through (obstacle evidence), flagged densely: most cells a ray
  // crosses hold none, and the flags are what it reads there.
  std::vector<std::uint8_t> obstacle(local.size(), 0);
  for (std::size_t k = 0; k < local.size(); ++k)
    obstacle[k] = local[k].cell && local[k].cell->log_odds > 0.0f;
  for (std::size_t i = 0; i < pts.size(); i += std::size_t(stride)) {
    const Eigen::Vector3d& p = pts[i];
    if (!p.allFinite()) continue;
    const Eigen::Vector3d d = p - sensor_m;
    const int ex = int(std::floor(p.x() / cm)), ey = int(std::floor(p.y() / cm));
    // Amanatides-Woo over the cells from the sensor's to the return's (exclusive).
    int x = sx, y = sy;
    const int step_x = d.x() > 0 ? 1 : -1, step_y = d.y() > 0 ? 1 : -1;
    const double inv_x = d.x() != 0 ? 1.0 / std::abs(d.x()) : 1e300;
    const double inv_y = d.y() != 0 ? 1.0 / std::abs(d.y()) : 1e300;
    const double fx = sensor_m.x() / cm - sx, fy = sensor_m.y() / cm - sy;
    double t_x = (step_x > 0 ? 1.0 - fx : fx) * cm * inv_x;
    double t_y = (step_y > 0 ? 1.0 - fy : fy) * cm * inv_y;
    const double dt_x = cm * inv_x, dt_y = cm * inv_y;
    double t_in = 0.0;
    for (int guard = 0; guard < 4 * (w + h) && (x != ex || y != ey); ++guard) {
      const double t_out = std::min({t_x, t_y, 1.0});
      const int lx = x - lo.x(), ly = y - lo.y();
      if (lx >= 0 && ly >= 0 && lx < w && ly < h && obstacle[std::size_t(ly) * w + lx]) {
        ScanCell& s = local[std::size_t(ly) * w + lx];
        const FusedCell* cell = s.cell;
        if (!s.seen_through) {
          const double ground = cell->layers[kElev];
          const double z = sensor_m.z() + 0.5 * (t_in + t_out) * d.z();
          const double above = z - ground;
          const double top = std::min<double>(cell->obstacle_top_m, clearance) - margin;
          if (std::isfinite(ground) && above >= min_h && above <= top) s.seen_through = true;
        }
      }
      if (t_out >= 1.0) break;
      t_in = t_out;
      if (t_x < t_y) {
        x += step_x;
        t_x += dt_x;
      } else {
        y += step_y;
        t_y += dt_y;
      }
    }
  }
}

}  // namespace fieldlidar::terrain::detail
