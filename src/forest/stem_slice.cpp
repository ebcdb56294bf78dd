// A stem slice's circle: RANSAC over three-point circles, refined on the inliers.
#include "fieldlidar/forest/stem_slice.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/segmentation/clustering.hpp"

namespace fieldlidar::forest {
namespace {

// The circle through three points; ok = false when they are (nearly) collinear.
Circle circle_through(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                      const Eigen::Vector2d& c) {
  Circle out;
  const Eigen::Vector2d ab = b - a, ac = c - a;
  const double d = 2 * (ab.x() * ac.y() - ab.y() * ac.x());
  if (std::abs(d) < 1e-12) return out;
  const double ab2 = ab.squaredNorm(), ac2 = ac.squaredNorm();
  const Eigen::Vector2d u((ac.y() * ab2 - ab.y() * ac2) / d, (ab.x() * ac2 - ac.x() * ab2) / d);
  out.center = a + u;
  out.radius_m = u.norm();
  out.ok = std::isfinite(out.radius_m);
  return out;
}

std::vector<Eigen::Vector2d> slice_within_band(std::span<const Eigen::Vector2d> points,
                                               const Circle& c, double band) {
  std::vector<Eigen::Vector2d> in;
  for (const auto& p : points)
    if (std::abs((p - c.center).norm() - c.radius_m) <= band) in.push_back(p);
  return in;
}

}  // namespace

Circle ransac_circle(std::span<const Eigen::Vector2d> points, const StemSliceConfig& config,
                     std::vector<Eigen::Vector2d>* inliers) {
  if (!(config.min_radius_m > 0) || !(config.max_radius_m > config.min_radius_m))
    throw Error("stem slice: radius bounds must satisfy 0 < min_radius_m < max_radius_m");
  if (!(config.inlier_band_m > 0)) throw Error("stem slice: inlier_band_m must be positive");
  if (config.iterations < 1) throw Error("stem slice: iterations must be at least 1");
  if (inliers) inliers->clear();
  Circle best;
  if (points.size() < std::max<std::size_t>(3, config.min_points)) return best;
  std::mt19937 rng(1);
  std::uniform_int_distribution<std::size_t> pick(0, points.size() - 1);
  std::size_t best_count = 0;
  for (int it = 0; it < config.iterations; ++it) {
    const std::size_t i = pick(rng), j = pick(rng), k = pick(rng);
    if (i == j || j == k || i == k) continue;
    const Circle c = circle_through(points[i], points[j], points[k]);
    if (!c.ok || c.radius_m < config.min_radius_m || c.radius_m > config.max_radius_m) continue;
    std::size_t count = 0;
    for (const auto& p : points)
      count += std::abs((p - c.center).norm() - c.radius_m) <= config.inlier_band_m;
    if (count > best_count) best_count = count, best = c;
  }
  if (best_count < config.min_points) return Circle{};
  // Refined on its inliers (a geometric fit), twice: the refined circle takes its own band.
  for (int round = 0; round < 2; ++round) {
    const auto in = slice_within_band(points, best, config.inlier_band_m);
    if (in.size() < config.min_points) break;
    const Circle refined = fit_circle(in, config.min_radius_m, config.max_radius_m, 20);
    if (!refined.ok) break;
    best = refined;
  }
  auto in = slice_within_band(points, best, config.inlier_band_m);
  double ss = 0;
  for (const auto& p : in) ss += std::pow((p - best.center).norm() - best.radius_m, 2);
  best.residual_m = in.empty() ? 0.0 : std::sqrt(ss / double(in.size()));
  best.ok = in.size() >= config.min_points;
  if (inliers) *inliers = std::move(in);
  return best;
}

double slice_thickness_m(const PointCloud& cloud) {
  double lo = INFINITY, hi = -INFINITY;
  for (const auto& p : cloud.points)
    if (p.is_valid()) lo = std::min(lo, double(p.z)), hi = std::max(hi, double(p.z));
  return hi >= lo ? hi - lo : NAN;
}

bool is_stem_slice(const PointCloud& cloud, const StemSliceConfig& config) {
  return slice_thickness_m(cloud) <= config.max_thickness_m;  // false for NaN
}

namespace {

// The slice's record of points `xy` (z range from `z`) and its circle.
StemSlice slice_of(std::span<const Eigen::Vector2d> xy, std::span<const double> z,
                   const StemSliceConfig& config) {
  StemSlice s;
  s.points = xy.size();
  if (!z.empty()) {
    const auto [lo, hi] = std::minmax_element(z.begin(), z.end());
    s.z_min_m = *lo;
    s.z_max_m = *hi;
  }
  std::vector<Eigen::Vector2d> in;
  s.circle = ransac_circle(xy, config, &in);
  s.inliers = in.size();
  if (s.circle.ok) s.arc_deg = arc_coverage_deg(in, s.circle.center);
  return s;
}

}  // namespace

std::vector<StemSlice> measure_slice_stems(const PointCloud& cloud, const StemSliceConfig& config) {
  segmentation::EuclideanClusterConfig cc;
  cc.tolerance_m = config.cluster_gap_m;
  cc.min_points = config.min_points;
  const auto clusters = segmentation::cluster_euclidean(cloud, {}, cc);
  std::vector<StemSlice> stems;
  for (const auto& cluster : clusters.clusters) {
    std::vector<Eigen::Vector2d> xy;
    std::vector<double> z;
    for (auto i : cluster.indices) {
      xy.emplace_back(cloud.points[i].x, cloud.points[i].y);
      z.push_back(cloud.points[i].z);
    }
    const std::size_t first = stems.size();
    for (int k = 0; k < config.max_stems_per_cluster && xy.size() >= config.min_points; ++k) {
      const StemSlice s = slice_of(xy, z, config);
      if (!s.circle.ok || s.arc_deg < config.min_arc_deg) break;
      // Two stems touch at most: a circle overlapping one already found is that stem's bark
      // or a branch beside it, and the cluster holds no more stems.
      const bool overlaps = std::any_of(stems.begin() + first, stems.end(), [&](const auto& o) {
        return (o.circle.center - s.circle.center).norm() <
               o.circle.radius_m + s.circle.radius_m - config.inlier_band_m;
      });
      if (overlaps) break;
      stems.push_back(s);
      // The stem's own points (its surface, rough bark just outside it, anything inside it)
      // leave the cluster.
      std::vector<Eigen::Vector2d> rest_xy;
      std::vector<double> rest_z;
      for (std::size_t i = 0; i < xy.size(); ++i)
        if ((xy[i] - s.circle.center).norm() > s.circle.radius_m + 3 * config.inlier_band_m) {
          rest_xy.push_back(xy[i]);
          rest_z.push_back(z[i]);
        }
      xy.swap(rest_xy);
      z.swap(rest_z);
    }
  }
  return stems;
}

StemSlice measure_stem_slice(const PointCloud& cloud, const StemSliceConfig& config) {
  std::vector<Eigen::Vector2d> xy;
  std::vector<double> z;
  for (const auto& p : cloud.points)
    if (p.is_valid()) {
      xy.emplace_back(p.x, p.y);
      z.push_back(p.z);
    }
  return slice_of(xy, z, config);
}

}  // namespace fieldlidar::forest
