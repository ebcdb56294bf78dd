// One tree per trunk stack: axis through the segment circles, base on the ground, DBH at 1.3 m.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <unordered_map>

#include <Eigen/Geometry>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/forest/trunks.hpp"

namespace fieldlidar::forest {
namespace {

// Ground points binned in 1 m cells for the base height near an axis.
class GroundIndex {
 public:
  GroundIndex(const PointCloud& cloud, std::span<const std::uint8_t> is_ground) {
    for (std::size_t i = 0; i < is_ground.size(); ++i)
      if (is_ground[i] && cloud.points[i].is_valid()) {
        const auto& p = cloud.points[i];
        cells_[key(cell(p.x), cell(p.y))].push_back(p.xyz().cast<double>());
      }
  }
  /// Median z of the ground points within radius of xy; NaN when there is none.
  double height_near(const Eigen::Vector2d& xy, double radius) const {
    std::vector<double> z;
    const int r = int(std::ceil(radius));
    for (int dx = -r; dx <= r; ++dx)
      for (int dy = -r; dy <= r; ++dy) {
        auto it = cells_.find(key(cell(xy.x()) + dx, cell(xy.y()) + dy));
        if (it == cells_.end()) continue;
        for (const auto& p : it->second)
          if ((p.head<2>() - xy).norm() <= radius) z.push_back(p.z());
      }
    if (z.empty()) return std::numeric_limits<double>::quiet_NaN();
    std::nth_element(z.begin(), z.begin() + z.size() / 2, z.end());
    return z[z.size() / 2];
  }

 private:
  static std::int64_t cell(double v) { return std::int64_t(std::floor(v)); }
  static std::int64_t key(std::int64_t x, std::int64_t y) { return (x << 32) ^ (y & 0xffffffff); }
  std::unordered_map<std::int64_t, std::vector<Eigen::Vector3d>> cells_;
};

struct Candidate {
  Tree tree;
  std::size_t dbh_points = 0;
};

std::optional<Candidate> tree_from_stack(const PointCloud& cloud,
                                         std::span<const ScanSegment> segments,
                                         const std::vector<std::size_t>& stack,
                                         const GroundIndex& ground, const TreeConfig& c) {
  // Circle per segment; its centre at the segment's height.
  std::vector<Eigen::Vector3d> centres;
  std::vector<Eigen::Vector2d> xy;
  for (auto s : stack) {
    xy.clear();
    for (auto i : segments[s].indices) xy.emplace_back(cloud.points[i].x, cloud.points[i].y);
    const Circle circle = fit_circle(xy, c.min_radius_m, c.max_radius_m);
    if (circle.ok && circle.residual_m <= c.max_residual_m)
      centres.emplace_back(circle.center.x(), circle.center.y(), segments[s].centroid.z());
  }
  if (centres.size() < 2) return std::nullopt;
  const Axis axis = fit_axis(centres, 0.05);
  if (!axis.ok || axis.inliers.size() < 2) return std::nullopt;
  const Eigen::Vector3d a = axis.direction;
  if (std::acos(std::clamp(a.z(), -1.0, 1.0)) * 180.0 / std::numbers::pi > c.max_tilt_deg)
    return std::nullopt;
  auto axis_at_z = [&](double z) -> Eigen::Vector3d {
    return axis.point + a * ((z - axis.point.z()) / a.z());
  };
  double z_low = 1e30;
  for (auto s : stack) z_low = std::min(z_low, segments[s].centroid.z());
  Candidate cand;
  Tree& t = cand.tree;
  double zg = ground.height_near(axis_at_z(z_low).head<2>(), c.ground_radius_m);
  t.ground_found = std::isfinite(zg);
  if (!t.ground_found) {
    zg = 1e30;
    for (auto s : stack)
      for (auto i : segments[s].indices) zg = std::min(zg, double(cloud.points[i].z));
  }
  if (z_low - zg > c.max_base_height_m) return std::nullopt;
  t.base_m = axis_at_z(zg);
  t.axis = a;
  const Eigen::Vector3d e1 = a.unitOrthogonal(), e2 = a.cross(e1);
  // Cross-section around breast height, in the plane perpendicular to the axis.
  std::vector<Eigen::Vector2d> ring_all, ring_dbh;
  double h_min = 1e30, h_max = -1e30;
  std::size_t lines_dbh = 0;
  for (auto s : stack) {
    bool in_window = false;
    for (auto i : segments[s].indices) {
      const Eigen::Vector3d v = cloud.points[i].xyz().cast<double>() - t.base_m;
      const double along = v.dot(a);
      const double h = along * a.z();
      h_min = std::min(h_min, h);
      h_max = std::max(h_max, h);
      const Eigen::Vector2d q(v.dot(e1), v.dot(e2));
      ring_all.push_back(q);
      if (std::abs(h - c.dbh_height_m) <= c.dbh_window_m) {
        ring_dbh.push_back(q);
        in_window = true;
      }
    }
    lines_dbh += in_window;
  }
  std::vector<Eigen::Vector2d> ring =
      (ring_dbh.size() >= 6 && lines_dbh >= 1) ? ring_dbh : ring_all;
  Circle circle = fit_circle(ring, c.min_radius_m, c.max_radius_m, 20);
  // Trim returns off the circle (twigs, mixed edge returns) and refit.
  for (int it = 0; it < 3 && circle.ok; ++it) {
    std::vector<Eigen::Vector2d> kept;
    const double thr = std::max(0.01, 2.5 * circle.residual_m);
    for (const auto& q : ring)
      if (std::abs((q - circle.center).norm() - circle.radius_m) <= thr) kept.push_back(q);
    if (kept.size() == ring.size() || kept.size() < 6) break;
    ring = std::move(kept);
    circle = fit_circle(ring, c.min_radius_m, c.max_radius_m, 20);
  }
  if (!circle.ok || circle.residual_m > c.max_residual_m) return std::nullopt;
  t.arc_deg = arc_coverage_deg(ring, circle.center);
  if (t.arc_deg < c.min_arc_deg) return std::nullopt;
  if (h_max - h_min < c.min_extent_seen_m) return std::nullopt;
  t.base_m += e1 * circle.center.x() + e2 * circle.center.y();
  t.dbh_m = 2 * circle.radius_m;
  t.residual_m = circle.residual_m;
  t.z_min_seen_m = h_min;
  t.z_max_seen_m = h_max;
  t.observations = stack.size();
  cand.dbh_points = ring.size();
  return cand;
}

}  // namespace

TreeResult extract_trees(const PointCloud& cloud, std::span<const std::uint8_t> is_ground,
                         const TreeConfig& config) {
  if (!is_ground.empty() && is_ground.size() != cloud.size())
    throw Error("forest: ground flags (" + std::to_string(is_ground.size()) +
                ") do not match the cloud (" + std::to_string(cloud.size()) + " points)");
  if (!(config.min_radius_m > 0) || !(config.max_radius_m > config.min_radius_m))
    throw Error("forest: radius bounds must satisfy 0 < min_radius_m < max_radius_m");
  TreeResult result;
  const auto segments = segment_scan_lines(cloud, is_ground, config.segments);
  result.segments = segments.size();
  const auto stacks = stack_segments(segments, config.stacks);
  result.stacks = stacks.size();
  const GroundIndex ground(cloud, is_ground);
  std::vector<Candidate> cands;
  for (const auto& st : stacks)
    if (auto c = tree_from_stack(cloud, segments, st, ground, config)) cands.push_back(*c);
  // Stacks of one stem (split by an occluder or a gap): the best supported one stays.
  std::sort(cands.begin(), cands.end(),
            [](const auto& a, const auto& b) { return a.dbh_points > b.dbh_points; });
  for (const auto& c : cands) {
    const Eigen::Vector3d p = c.tree.at_height(config.dbh_height_m);
    bool dup = false;
    for (const auto& t : result.trees)
      dup |= (t.at_height(config.dbh_height_m) - p).head<2>().norm() <
             config.merge_distance_m + 0.5 * (t.dbh_m + c.tree.dbh_m) / 2;
    if (dup) continue;
    result.trees.push_back(c.tree);
    result.trees.back().id = std::uint32_t(result.trees.size());
  }
  return result;
}

}  // namespace fieldlidar::forest
