/// Trench shadows of one scan (negative_obstacle.hpp): returns grouped by azimuth column, each
/// column walked outwards against the line of its near ground.
#include "fieldlidar/terrain/negative_obstacle.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace fieldlidar::terrain {

namespace {

/// One return of a column: horizontal range and height (m, from the sensor's foot), its index.
struct ColumnReturn {
  float r, z;
  std::uint32_t index;
  bool ground;
};

/// A sunk return waiting for the ground beyond to rise back: where its beam crossed the near
/// ground's line (range, m), where it returned, and its depth below the line there.
struct Sunk {
  float r_cross, r, z, depth;
  std::uint32_t index;
};

}  // namespace

TrenchScan find_trench_shadows(std::span<const Eigen::Vector3d> points_m,
                               std::span<const std::uint8_t> is_ground,
                               const Eigen::Vector3d& sensor_m, double max_slope_deg,
                               const NegativeObstacleConfig& config) {
  TrenchScan out;
  if (!config.enabled || points_m.size() != is_ground.size()) return out;
  const double column_rad = config.column_width_deg * std::numbers::pi / 180.0;
  if (!(column_rad > 0)) return out;
  const int columns = std::max(1, int(std::ceil(2 * std::numbers::pi / column_rad)));
  // Counting sort of the returns into their columns.
  std::vector<int> column_of(points_m.size(), -1);
  std::vector<std::uint32_t> start(std::size_t(columns) + 1, 0);
  for (std::size_t i = 0; i < points_m.size(); ++i) {
    const Eigen::Vector3d& p = points_m[i];
    if (!p.allFinite()) continue;
    const double dx = p.x() - sensor_m.x(), dy = p.y() - sensor_m.y();
    if (dx * dx + dy * dy < config.min_range_m * config.min_range_m) continue;
    const double a = std::atan2(dy, dx) + std::numbers::pi;  // [0, 2 pi]
    column_of[i] = std::min(columns - 1, int(a / column_rad));
    ++start[std::size_t(column_of[i]) + 1];
  }
  for (int c = 0; c < columns; ++c) start[c + 1] += start[c];
  std::vector<ColumnReturn> sorted(start.back());
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  for (std::size_t i = 0; i < points_m.size(); ++i) {
    if (column_of[i] < 0) continue;
    const Eigen::Vector3d& p = points_m[i];
    const double dx = p.x() - sensor_m.x(), dy = p.y() - sensor_m.y();
    sorted[fill[std::size_t(column_of[i])]++] = {float(std::sqrt(dx * dx + dy * dy)),
                                                 float(p.z() - sensor_m.z()), std::uint32_t(i),
                                                 is_ground[i] != 0};
  }
  const float max_rise = float(std::tan(max_slope_deg * std::numbers::pi / 180.0));
  const float min_depth = float(config.min_depth_m);
  const float curvature_half = 0.5f * float(config.ground_curvature_per_m);
  std::vector<Sunk> sunk;
  for (int c = 0; c < columns; ++c) {
    const auto first = sorted.begin() + start[c], last = sorted.begin() + start[c + 1];
    std::sort(first, last, [](const ColumnReturn& a, const ColumnReturn& b) { return a.r < b.r; });
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
