/// Trench shadows of one scan (negative_obstacle.hpp): returns grouped by azimuth column, each
/// column walked outwards against the line of its near ground.
#include "fieldlidar/terrain/negative_obstacle.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace fieldlidar::terrain {

namespace {

inline int fast_azimuth_column(double dx, double dy, double column_rad, int columns) {
  // atan(t) on [0, 1] within 1e-5 rad (Abramowitz & Stegun 4.4.49), folded into the octants.
  const double ax = std::abs(dx), ay = std::abs(dy);
  const bool steep = ay > ax;
  const double t = steep ? ax / ay : ay / ax, t2 = t * t;
  double a =
      t * (0.9998660 + t2 * (-0.3302995 + t2 * (0.1801410 + t2 * (-0.0851330 + t2 * 0.0208351))));
  if (steep) a = 0.5 * std::numbers::pi - a;
  if (dx < 0) a = std::numbers::pi - a;
  if (dy < 0) a = -a;
  const double u = (a + std::numbers::pi) * (1.0 / column_rad);  // only near the edges exact
  const double edge = std::floor(u + 0.5);                       // the nearest column edge
  constexpr double kMargin_rad = 1e-4;                           // ten times the arctangent's error
  if (!(std::abs(u - edge) * column_rad > kMargin_rad)) {
    const double exact = std::atan2(dy, dx) + std::numbers::pi;  // [0, 2 pi]
    return std::min(columns - 1, int(exact / column_rad));
  }
  return std::min(columns - 1, int(u));
}

}  // namespace

namespace detail {

int azimuth_column(double dx, double dy, double column_rad, int columns) {
  return fast_azimuth_column(dx, dy, column_rad, columns);
}

}  // namespace detail

using detail::ColumnReturn;
using detail::Sunk;

TrenchScan find_trench_shadows(std::span<const Eigen::Vector3d> points_m,
                               std::span<const std::uint8_t> is_ground,
                               const Eigen::Vector3d& sensor_m, double max_slope_deg,
                               const NegativeObstacleConfig& config) {
  TrenchScratch scratch;
  return find_trench_shadows(points_m, is_ground, sensor_m, max_slope_deg, config, scratch);
}

TrenchScan find_trench_shadows(std::span<const Eigen::Vector3d> points_m,
                               std::span<const std::uint8_t> is_ground,
                               const Eigen::Vector3d& sensor_m, double max_slope_deg,
                               const NegativeObstacleConfig& config, TrenchScratch& scratch) {
  TrenchScan out;
  if (!config.enabled || points_m.size() != is_ground.size()) return out;
  const double column_rad = config.column_width_deg * std::numbers::pi / 180.0;
  if (!(column_rad > 0)) return out;
  const int columns = std::max(1, int(std::ceil(2 * std::numbers::pi / column_rad)));
  // Counting sort of the returns into their columns.
  auto& column_of = scratch.column_of;
  auto& start = scratch.start;
  auto& by_index = scratch.by_index;
  column_of.assign(points_m.size(), -1);
  start.assign(std::size_t(columns) + 1, 0);
  by_index.resize(points_m.size());
  const double min_range2 = config.min_range_m * config.min_range_m;
  for (std::size_t i = 0; i < points_m.size(); ++i) {
    const Eigen::Vector3d& p = points_m[i];
    if (!p.allFinite()) continue;
    const double dx = p.x() - sensor_m.x(), dy = p.y() - sensor_m.y();
    const double r2 = dx * dx + dy * dy;
    if (r2 < min_range2) continue;
    if (dx == 0 && dy == 0) {
      column_of[i] =
          std::min(columns - 1, int((std::atan2(dy, dx) + std::numbers::pi) / column_rad));
    } else {
      column_of[i] = fast_azimuth_column(dx, dy, column_rad, columns);
    }
    by_index[i] = {float(std::sqrt(r2)), float(p.z() - sensor_m.z()), std::uint32_t(i),
                   is_ground[i] != 0};
    ++start[std::size_t(column_of[i]) + 1];
  }
  for (int c = 0; c < columns; ++c) start[c + 1] += start[c];
  auto& sorted = scratch.sorted;
  sorted.resize(start.back());
  scratch.fill.assign(start.begin(), start.end() - 1);
  for (std::size_t i = 0; i < points_m.size(); ++i)
    if (column_of[i] >= 0) sorted[scratch.fill[std::size_t(column_of[i])]++] = by_index[i];
  const float max_rise = float(std::tan(max_slope_deg * std::numbers::pi / 180.0));
  const float min_depth = float(config.min_depth_m);
  const float curvature_half = 0.5f * float(config.ground_curvature_per_m);
  auto& sunk = scratch.sunk;
  for (int c = 0; c < columns; ++c) {
    const auto first = sorted.begin() + start[c], last = sorted.begin() + start[c + 1];
    // Sorted by range; a column already in strictly increasing range order (no ties, so one
    // order only) is left as it is.
    const auto nearer = [](const ColumnReturn& a, const ColumnReturn& b) { return a.r < b.r; };
    const auto not_rising = [](const ColumnReturn& a, const ColumnReturn& b) { return a.r >= b.r; };
    if (std::adjacent_find(first, last, not_rising) != last) std::sort(first, last, nearer);
    // The near ground's line: through the last ground return (r_a, z_a), with the slope from
    // an earlier one at least kBaseline_m nearer (r_b, z_b); none until two such are seen.
    constexpr float kBaseline_m = 0.5f;
    bool line = false, based = false;
    float r_a = 0, z_a = 0, r_b = 0, z_b = 0, slope = 0, deepest = 0;
    const auto take_ground = [&](const ColumnReturn& q) {
      if (!based) {
        r_b = q.r, z_b = q.z, based = true;
      } else if (q.r - r_b >= kBaseline_m) {
        slope = std::clamp((q.z - z_b) / (q.r - r_b), -max_rise, max_rise);
        r_b = q.r, z_b = q.z, line = true;
      }
      r_a = q.r, z_a = q.z;
    };
    sunk.clear();
    for (auto q = first; q != last; ++q) {
      // Too far beyond the near ground to judge by its line, and (with sunk returns waiting)
      // too far beyond the last of them to be the trench's far side.
      const float reach = float(config.max_extrapolation_m);
      if (line && q->r - (sunk.empty() ? r_a : sunk.back().r) > reach) {
        line = based = false;
        sunk.clear();
        deepest = 0;
      }
      if (!line) {  // an obstacle between two ground returns breaks the line they would make
        if (q->ground)
          take_ground(*q);
        else
          based = false;
        continue;
      }
      const float depth = z_a + slope * (q->r - r_a) - q->z;
      const float ahead = q->r - r_a;
      if (depth >= min_depth + curvature_half * ahead * ahead) {
        if (ahead > reach) continue;  // sunk by the ground's curvature as much
        // Sunk: its beam (descending t per metre) fell below the line at r_cross.
        const float t = -q->z / q->r;
        if (t + slope <= 1e-3f) continue;
        const float r_cross = std::max(r_a, q->r - depth / (t + slope));
        sunk.push_back({r_cross, q->r, q->z, depth, q->index});
        deepest = std::max(deepest, depth);
        continue;
      }
      if (!q->ground) {
        // An obstacle on the ground (a rock, a bush, a step's face): what lies behind it is its
        // shadow, and the ground beyond starts a new line; unless it stands beyond sunk returns
        // (on the trench's far lip), whose far ground may still show beyond it.
        if (depth < 0 && sunk.empty()) line = based = false;
        continue;
      }
      if (!sunk.empty()) {
        // A return rising over the last sunk one more steeply than 1:1 is a face (a rock's kept
        // as ground, or the far wall's), not the ground beyond: it neither ends nor breaks the
        // trench.
        const float rise = q->z - sunk.back().z;
        if (rise > q->r - sunk.back().r) continue;
        // Ground again: a trench when it rose back towards the near ground (but not far above
        // it: a bush's top kept as ground), within max_span_m.
        const bool rose = depth <= float(config.max_far_depth_share) * deepest &&
                          depth >= -float(config.max_far_rise_m);
        const bool narrow = sunk.back().r - sunk.front().r_cross <= float(config.max_span_m);
        if (rose && narrow)
          for (const Sunk& s : sunk) {
            const Eigen::Vector3d& p = points_m[s.index];
            const Eigen::Vector2d dir = (p.head<2>() - sensor_m.head<2>()) / std::max(1e-6f, s.r);
            out.shadows.push_back(
                {sensor_m.head<2>() + double(s.r_cross) * dir, p.head<2>(), s.depth});
          }
        sunk.clear();
        deepest = 0;
      } else if (depth < -min_depth) {
        // Ground rising above the line as much (a low rock kept as ground, the foot of a
        // slope): a new line starts there.
        line = based = false;
      } else {
        out.level_ground.push_back(q->index);
      }
      take_ground(*q);
    }
  }
  return out;
}

}  // namespace fieldlidar::terrain
