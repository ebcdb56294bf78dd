// Levelling before the robust ground: the polar grid's local planes, its slope bound and its
// prior plane assume a roughly level sensor. A sensor tilted by 20-35 deg (handheld, a robot on
// a slope) sees its ground as a steep plane and the robust ground loses most of it. The cloud is
// rotated so that the up direction -- measured, or the normal of the dominant ground plane below
// the sensor -- becomes z, segmented, and the labels map back one to one. A level sensor costs
// one pass over about 8,000 of the points and a plane fit through a few hundred cell minima.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <numbers>
#include <span>
#include <vector>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "fieldlidar/core/rotate_points.hpp"
#include "fieldlidar/segmentation/ground.hpp"
#include "ground_plane.hpp"
#include "polar_grid.hpp"

namespace fieldlidar::segmentation {
namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

// Lowest return (along the lidar z) of each cell of 36 sectors x 1 m rings between 1 m and
// near_range_m, from every `stride`-th point; `flip`: of the cloud turned over about x (y and z
// negated), as an upside-down sensor's sweep would be seen upright.
std::vector<Eigen::Vector3f> cell_minima(const PointCloud& cloud, double near_range_m,
                                         std::size_t stride, bool flip) {
  constexpr int kSectors = 36;
  constexpr float kInner = 1.0f;
  const int rings = std::max(1, int(std::ceil(near_range_m - kInner)));
  std::vector<Eigen::Vector3f> lowest(std::size_t(kSectors) * rings,
                                      Eigen::Vector3f(0, 0, std::numeric_limits<float>::max()));
  const float inner2 = kInner * kInner, near2 = float(near_range_m * near_range_m);
  const float sectors_per_rad = float(kSectors / (2 * std::numbers::pi));
  for (std::size_t i = 0; i < cloud.size(); i += stride) {
    Point p = cloud.points[i];
    if (!valid_point(p)) continue;
    if (flip) p.y = -p.y, p.z = -p.z;
    const float r2 = p.x * p.x + p.y * p.y;
    if (r2 < inner2 || r2 >= near2) continue;
    const int ring = std::min(rings - 1, int(std::sqrt(r2) - kInner));
    const float az = fast_atan2(p.y, p.x) + float(std::numbers::pi);
    const int sector = std::clamp(int(az * sectors_per_rad), 0, kSectors - 1);
    Eigen::Vector3f& low = lowest[std::size_t(sector) * rings + ring];
    if (p.z < low.z()) low = {p.x, p.y, p.z};
  }
  std::vector<Eigen::Vector3f> out;
  for (const Eigen::Vector3f& l : lowest)
    if (l.z() != std::numeric_limits<float>::max()) out.push_back(l);
  return out;
}

// Plane n . p + d = 0 with n the unit up normal; d is the sensor's height above it.
struct Plane {
  Eigen::Vector3d n{0, 0, 1};
  double d = 0;
  double distance(const Eigen::Vector3f& p) const { return n.dot(p.cast<double>()) + d; }
};

// Least-squares plane (smallest principal axis) of the lows within band_m of `plane`.
bool refine(std::span<const Eigen::Vector3f> lows, double band_m, Plane& plane,
            std::size_t& support) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  std::size_t n = 0;
  for (const Eigen::Vector3f& l : lows)
    if (std::abs(plane.distance(l)) <= band_m) {
      mean += l.cast<double>();
      ++n;
    }
  if (n < 6) return false;
  mean /= double(n);
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3f& l : lows)
    if (std::abs(plane.distance(l)) <= band_m) {
      const Eigen::Vector3d q = l.cast<double>() - mean;
      cov.noalias() += q * q.transpose();
    }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
  Eigen::Vector3d normal = es.eigenvectors().col(0);
  if (normal.z() < 0) normal = -normal;
  plane.n = normal;
  plane.d = -normal.dot(mean);
  support = n;
  return true;
}

// The ground plane below the sensor from the cell minima (estimate_up).
// `level_fit`: set when the level plane held (no search was needed).
UpEstimate estimate_from_lows(const std::vector<Eigen::Vector3f>& lows,
                              const LevellingConfig& config, bool& level_fit) {
  level_fit = false;
  UpEstimate out;
  if (lows.size() < 12) return out;
  // Level enough already? A trimmed fit from the level plane, its tilt bounded by the tolerance,
  // that holds a quarter of the lows with (almost) none well below it is the ground: no search.
  // Seen from a tilted sensor, half the ground lies below such a plane, or the fit leans on its
  // bound (a fit within 1 deg of it is not taken).
  const NearGroundPlane level = fit_plane_to_lows(lows, config.level_tolerance_deg / kDegPerRad);
  if (level.found) {
    Plane plane;
    plane.n = Eigen::Vector3d(-level.a, -level.b, 1.0).normalized();
    plane.d = -level.c * plane.n.z();
    std::size_t inliers = 0, below = 0;
    for (const Eigen::Vector3f& l : lows) {
      const double dist = plane.distance(l);
      inliers += std::abs(dist) <= config.inlier_band_m;
      below += dist < -config.below_band_m;
    }
    const double tilt_deg = std::acos(std::clamp(plane.n.z(), -1.0, 1.0)) * kDegPerRad;
    if (plane.d > 0.1 && 4 * inliers >= lows.size() && 50 * below <= lows.size() &&
        tilt_deg <= config.level_tolerance_deg - 1.0) {
      out.up = plane.n;
      out.tilt_deg = tilt_deg;
      out.sensor_height_m = plane.d;
      out.support = inliers;
      out.found = true;
      level_fit = true;
      return out;
    }
  }
  const double min_nz = std::cos(config.max_tilt_deg / kDegPerRad);
  // Deterministic hypotheses: a fixed-seed linear congruential generator.
  std::uint64_t state = 0x9E3779B97F4A7C15ull;
  const auto draw = [&state, n = lows.size()] {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return std::size_t((state >> 33) % n);
  };
  Plane best;
  double best_score = -std::numeric_limits<double>::infinity();
  for (int h = 0; h < config.hypotheses; ++h) {
    const Eigen::Vector3d a = lows[draw()].cast<double>(), b = lows[draw()].cast<double>(),
                          c = lows[draw()].cast<double>();
    Eigen::Vector3d n = (b - a).cross(c - a);
    const double len = n.norm();
    if (!(len > 1e-3)) continue;  // degenerate sample
    n /= len;
    if (n.z() < 0) n = -n;
    if (n.z() < min_nz) continue;
    const Plane plane{n, -n.dot(a)};
    if (!(plane.d > 0.1)) continue;  // the sensor stands above its ground
    double inliers = 0, below = 0;
    for (const Eigen::Vector3f& l : lows) {
      const double dist = plane.distance(l);
      inliers += std::abs(dist) <= config.inlier_band_m;
      below += dist < -config.below_band_m;
    }
    // The ground is the lowest large plane: lows well below a candidate count against it.
    const double score = inliers - 2.0 * below;
    if (score > best_score) {
      best_score = score;
      best = plane;
    }
  }
  if (!(best_score > 0)) return out;
  std::size_t support = 0;
  for (const double band : {2.0 * config.inlier_band_m, config.inlier_band_m})
    if (!refine(lows, band, best, support)) return out;
  out.up = best.n;
  out.tilt_deg = std::acos(std::clamp(best.n.z(), -1.0, 1.0)) * kDegPerRad;
  out.sensor_height_m = best.d;
  out.support = support;
  out.found = true;
  return out;
}

}  // namespace

UpEstimate estimate_up(const PointCloud& cloud, const LevellingConfig& config) {
  UpEstimate out;
  if (config.up.allFinite() && config.up.norm() > 0) {
    out.up = config.up.normalized();
    out.tilt_deg = std::acos(std::clamp(out.up.z(), -1.0, 1.0)) * kDegPerRad;
    out.found = true;
    return out;
  }
  // About 8,000 returns are plenty for the lowest return of 1 m cells near the sensor (reading a
  // whole 64-ring sweep costs more than the rest of the estimate).
  const std::size_t stride = std::max<std::size_t>(1, cloud.size() / 8000);
  bool level = false;
  out = estimate_from_lows(cell_minima(cloud, config.near_range_m, stride, false), config, level);
  if (level) return out;
  // A sensor turned over sees its ground above it: the lowest returns it has are tree tops and
  // hedges, which may make a plane of their own, but the ground makes a far larger one (a
  // turned-over sweep of the lawn scene: hedge tops upright, 4 times their support turned over;
  // RELLIS-3D 000001 upright: its ground 43 lows, the vehicle's roof 68 turned over).
  UpEstimate over =
      estimate_from_lows(cell_minima(cloud, config.near_range_m, stride, true), config, level);
  if (!over.found || over.support < 30 || (out.found && over.support <= 2 * out.support))
    return out;
  over.up = Eigen::Vector3d(over.up.x(), -over.up.y(), -over.up.z());
  over.tilt_deg = std::acos(std::clamp(over.up.z(), -1.0, 1.0)) * kDegPerRad;
  over.upside_down = true;
  return over;
}

Eigen::Matrix3d level_rotation(const UpEstimate& up) {
  // The levelled frame's axes in lidar coordinates are the rows: z the ground's up, x the lidar's
  // own x laid level (its y when x points nearly up or down), y completing them. Unlike the
  // smallest rotation, this keeps the heading of a sensor turned over: 180 deg from up, the
  // smallest rotation's axis is any level one, set by the last degree of the estimate.
  const Eigen::Vector3d z = up.up.normalized();
  Eigen::Vector3d x = Eigen::Vector3d::UnitX() - z.x() * z;
  if (x.norm() < 0.1) x = (Eigen::Vector3d::UnitY() - z.y() * z).cross(z);
  x.normalize();
  Eigen::Matrix3d R;
  R.row(0) = x.transpose();
  R.row(1) = z.cross(x).transpose();
  R.row(2) = z.transpose();
  return R;
}

GroundResult ground_robust_levelled(const PointCloud& cloud, const SensorModel& sensor,
                                    const RobustGroundConfig& robust,
                                    const LevellingConfig& levelling) {
  if (!levelling.enabled) return ground_robust(cloud, sensor, robust);
  const UpEstimate up = estimate_up(cloud, levelling);
  if (!up.found || up.tilt_deg <= levelling.level_tolerance_deg) {
    GroundResult r = ground_robust(cloud, sensor, robust);
    r.tilt_deg = up.tilt_deg;
    r.up_found = up.found;
    return r;
  }
  PointCloud level = cloud;
  rotate_points(level, level_rotation(up).cast<float>());
  GroundResult r = ground_robust(level, sensor, robust);
  r.tilt_deg = up.tilt_deg;
  r.levelled = true;
  r.upside_down = up.upside_down;
  return r;
}

}  // namespace fieldlidar::segmentation
