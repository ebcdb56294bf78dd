// One tree per stem: stacks on one axis joined (breaks), a cylinder fitted to the stem around
// breast height (branches and twigs trimmed), the base on the ground and DBH at 1.3 m.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>

#include <Eigen/Geometry>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/forest/trunks.hpp"
#include "ground_index.hpp"
#include "silhouette.hpp"

namespace fieldlidar::forest {
namespace {

// Stacks of one stem: their axis from the segment centroids and every point index they hold.
struct Stem {
  Axis axis;
  std::vector<std::uint32_t> points;
  std::vector<std::size_t> segment_ids;
  std::size_t segments = 0;
  double z_low = 1e30, z_high = -1e30;
};

double horizontal_offset(const Axis& a, const Eigen::Vector3d& p) {
  const Eigen::Vector3d on = a.point + a.direction * ((p.z() - a.point.z()) / a.direction.z());
  return (on - p).head<2>().norm();
}

// Stacks in order of size; one whose centroids all lie on a bigger stem's axis joins that stem.
std::vector<Stem> join_stacks(std::span<const ScanSegment> segments,
                              const std::vector<std::vector<std::size_t>>& stacks,
                              const TreeConfig& c) {
  std::vector<std::size_t> order(stacks.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](auto a, auto b) { return stacks[a].size() > stacks[b].size(); });
  std::vector<Stem> stems;
  std::vector<Eigen::Vector3d> centroids;
  for (auto k : order) {
    centroids.clear();
    for (auto s : stacks[k]) centroids.push_back(segments[s].centroid);
    Stem* host = nullptr;
    for (auto& st : stems) {
      bool on = true;
      for (const auto& p : centroids) on &= horizontal_offset(st.axis, p) <= c.join_distance_m;
      if (on) {
        host = &st;
        break;
      }
    }
    if (!host) {
      Stem st;
      st.axis = fit_axis(centroids, 0.05);
      if (!st.axis.ok) continue;
      stems.push_back(std::move(st));
      host = &stems.back();
    }
    for (auto s : stacks[k]) {
      host->points.insert(host->points.end(), segments[s].indices.begin(),
                          segments[s].indices.end());
      host->z_low = std::min(host->z_low, segments[s].centroid.z());
      host->z_high = std::max(host->z_high, segments[s].centroid.z());
    }
    host->segments += stacks[k].size();
    host->segment_ids.insert(host->segment_ids.end(), stacks[k].begin(), stacks[k].end());
  }
  return stems;
}

// Share of the scan lines between a stem's lowest and highest that hold a segment of it: a
// trunk fills most of them, a shrub or crown gives scattered hits.
double line_fill(std::span<const ScanSegment> segments, const Stem& stem) {
  std::vector<int> lines;
  for (auto s : stem.segment_ids) lines.push_back(segments[s].line);
  std::sort(lines.begin(), lines.end());
  lines.erase(std::unique(lines.begin(), lines.end()), lines.end());
  if (lines.empty()) return 0.0;
  return double(lines.size()) / double(lines.back() - lines.front() + 1);
}

// Whether the scan line above a stem's highest segment passed over it at its bearing.
bool ends_below_next_line(std::span<const ScanSegment> segments, const RingIndex& rings,
                          const Stem& stem, const TreeConfig& c) {
  const ScanSegment* top = nullptr;
  for (auto s : stem.segment_ids)
    if (!top || segments[s].line > top->line) top = &segments[s];
  if (!top) return false;
  const Eigen::Vector2d xy = top->centroid.head<2>();
  const double range = xy.norm();
  if (!(range > 0)) return false;
  const double half = std::atan2(0.5 * top->width_m, range) + 2 * rings.step(top->line);
  return rings.passed_over(top->line + 1, std::atan2(xy.y(), xy.x()), half, range + c.top_clear_m);
}

std::optional<Tree> tree_from_stem(const PointCloud& cloud, std::span<const ScanSegment> segments,
                                   const RingIndex* rings, const Stem& stem,
                                   const GroundIndex& ground, const TreeConfig& c) {
  const Axis& axis = stem.axis;
  Eigen::Vector3d a = axis.direction;
  if (std::acos(std::clamp(a.z(), -1.0, 1.0)) * 180.0 / std::numbers::pi > c.max_tilt_deg)
    return std::nullopt;
  auto axis_at_z = [&](const Eigen::Vector3d& p0, const Eigen::Vector3d& d, double z) {
    return Eigen::Vector3d(p0 + d * ((z - p0.z()) / d.z()));
  };
  Tree t;
  const Eigen::Vector2d foot = axis_at_z(axis.point, a, stem.z_low).head<2>();
  double zg = ground.height_near(foot, c.ground_radius_m);
  // A cloud without rings (a plot; its ground from the grid): ground taken from the lowest
  // returns of cells whose floor was never seen (under a dense crown) lies on branches, and the
  // lower ground around replaces it.
  if (!cloud.fields.ring) {
    const double zg_wide = ground.quantile_near(foot, c.ground_check_radius_m, 0.1);
    if (!std::isfinite(zg) || zg - zg_wide > c.max_ground_step_m) zg = zg_wide;
  }
  double z_lowest = 1e30;
  for (auto i : stem.points) z_lowest = std::min(z_lowest, double(cloud.points[i].z));
  // A sweep whose view of the stem's foot is blocked (a shrub or a stem in front): the floor
  // plane around it, which the lowest stem point bounds from above.
  if (!std::isfinite(zg) && cloud.fields.ring)
    zg = std::min(ground.plane_height_near(foot, c.ground_check_radius_m), z_lowest);
  t.ground_found = std::isfinite(zg);
  if (!t.ground_found) zg = z_lowest;
  if (stem.z_low - zg > c.max_base_height_m) return std::nullopt;  // a fork or crown branch
  // A shrub or crown gives scattered hits over a metre or more (a sweep's lines or a plot's
  // slices).
  if ((rings || c.plot_full_view) && line_fill(segments, stem) < c.min_line_fill)
    return std::nullopt;
  // Stem points within the window around breast height, along the stacked axis.
  const Eigen::Vector3d base0 = axis_at_z(axis.point, a, zg);
  std::vector<Eigen::Vector3d> band;
  double h_min = 1e30, h_max = -1e30, band_lo = 1e30, band_hi = -1e30;
  for (auto i : stem.points) {
    const Eigen::Vector3d p = cloud.points[i].xyz().cast<double>();
    const double h = (p - base0).dot(a) * a.z();
    h_min = std::min(h_min, h);
    h_max = std::max(h_max, h);
    if (std::abs(h - c.dbh_height_m) <= c.dbh_window_m) {
      band.push_back(p);
      band_lo = std::min(band_lo, h);
      band_hi = std::max(band_hi, h);
    }
  }
  if (band.size() < c.min_stem_points || h_max - h_min < c.min_extent_seen_m) return std::nullopt;
  if (rings && h_max < c.min_top_seen_m && ends_below_next_line(segments, *rings, stem, c))
    return std::nullopt;
  // A plot seen from all round sees its stems down to the floor: one that starts above breast
  // height is a branch or a piece of crown, and its circle at 1.3 m would be drawn where nothing
  // was seen.
  if (!cloud.fields.ring && c.plot_full_view && h_min > c.plot_max_stem_start_m)
    return std::nullopt;
  CylinderFitConfig fc = c.cylinder;
  fc.min_radius_m = c.min_radius_m;
  fc.max_radius_m = c.max_radius_m;
  fc.fit_direction = fc.fit_direction && band_hi - band_lo >= c.min_fit_span_m;
  if (cloud.fields.ring) fc.start_bin_m = 0.0;  // a sweep's few lines a bin: one fit starts it
  const Cylinder cyl = fit_cylinder(band, axis_at_z(axis.point, a, zg + c.dbh_height_m), a, fc);
  const double max_residual = cloud.fields.ring ? c.max_residual_m : c.plot_max_residual_m;
  if (!cyl.ok || cyl.residual_m > max_residual) return std::nullopt;
  a = cyl.direction;
  if (std::acos(std::clamp(a.z(), -1.0, 1.0)) * 180.0 / std::numbers::pi > c.max_tilt_deg)
    return std::nullopt;
  // Arc seen: kept points around the axis, in the plane across it.
  const Eigen::Vector3d e1 = a.unitOrthogonal(), e2 = a.cross(e1);
  std::vector<Eigen::Vector2d> ring;
  for (auto i : cyl.inliers) {
    const Eigen::Vector3d v = band[i] - cyl.point;
    ring.emplace_back(v.dot(e1), v.dot(e2));
  }
  t.arc_deg = arc_coverage_deg(ring, Eigen::Vector2d::Zero());
  if (t.arc_deg < c.min_arc_deg) return std::nullopt;
  t.axis = a;
  t.base_m = axis_at_z(cyl.point, a, zg);
  t.dbh_m = 2 * cyl.radius_m;
  if (rings) {
    const auto sil = silhouette_radius(cloud, segments, *rings, stem.segment_ids, cyl, zg, c);
    double r = sil.radius_m;
    if (!std::isfinite(r)) {
      if (!std::isfinite(sil.guess_m)) return std::nullopt;  // too few lines near breast height
      // Every line cut by an occluder over a narrow sliver: a guess, marked as such.
      r = sil.guess_m;
      t.dbh_uncertain = true;
    }
    t.dbh_m = 2 * std::clamp(r, c.min_radius_m, c.max_radius_m);
    // The axis placed along the sensor's line of sight from the mean range of the stem's
    // returns: on a stem uniformly sampled across its visible width, the mean depth behind the
    // nearest point is pi/4 of the radius. The fit's centre rests on the arc's curvature, which
    // few returns a line and range noise leave loose.
    {
      double sum_range = 0, sum_z = 0;
      for (auto i : cyl.inliers) {
        sum_range += band[i].head<2>().norm();
        sum_z += band[i].z();
      }
      const double n = double(cyl.inliers.size());
      const Eigen::Vector3d q = axis_at_z(cyl.point, a, sum_z / n);
      const Eigen::Vector2d bearing = q.head<2>().normalized();
      const double d = sum_range / n + std::numbers::pi / 4 * t.dbh_m / 2;
      t.base_m.head<2>() += bearing * d - q.head<2>();
    }
  }
  t.residual_m = cyl.residual_m;
  t.z_min_seen_m = h_min;
  t.z_max_seen_m = h_max;
  t.observations = stem.segments;
  return t;
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
  std::optional<RingIndex> rings;
  if (config.silhouette_dbh && cloud.fields.ring && !stacks.empty()) rings.emplace(cloud);
  std::vector<std::pair<Tree, std::size_t>> cands;
  for (const auto& stem : join_stacks(segments, stacks, config))
    if (auto t = tree_from_stem(cloud, segments, rings ? &*rings : nullptr, stem, ground, config))
      cands.emplace_back(*t, stem.points.size());
  // Stems left apart (split by an occluder): the best supported one stays.
  std::sort(cands.begin(), cands.end(),
            [](const auto& a, const auto& b) { return a.second > b.second; });
  for (const auto& [tree, n] : cands) {
    const Eigen::Vector3d p = tree.at_height(config.dbh_height_m);
    bool dup = false;
    for (const auto& t : result.trees)
      dup |= (t.at_height(config.dbh_height_m) - p).head<2>().norm() <
             config.merge_distance_m + 0.5 * (t.dbh_m + tree.dbh_m) / 2;
    if (dup) continue;
    result.trees.push_back(tree);
    result.trees.back().id = std::uint32_t(result.trees.size());
  }
  return result;
}

}  // namespace fieldlidar::forest
