#pragma once
/// \file Point clouds: one LiDAR sweep (or any set of points) with per-point ring and time.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include <Eigen/Core>

namespace fieldlidar {

/// One LiDAR return. 24 bytes, trivially copyable, so a cloud is one contiguous array.
struct Point {
  float x = 0.f;          ///< m, in the cloud's frame (x forward, y left, z up)
  float y = 0.f;          ///< m
  float z = 0.f;          ///< m
  float intensity = 0.f;  ///< sensor units (reflectivity or signal), 0 when unknown
  float time = 0.f;       ///< s, offset from the sweep start (PointCloud::stamp_s); 0 when unknown
  std::uint16_t ring = kNoRing;  ///< beam index, 0 = lowest beam; kNoRing when unknown
  std::uint16_t reserved = 0;

  static constexpr std::uint16_t kNoRing = std::numeric_limits<std::uint16_t>::max();

  Eigen::Vector3f xyz() const { return {x, y, z}; }
  /// True when x, y and z are finite and not the all-zero "no return" marker. Inline: every
  /// per-point loop calls it.
  bool is_valid() const {
    return std::isfinite(x) && std::isfinite(y) && std::isfinite(z) &&
           (x != 0.f || y != 0.f || z != 0.f);
  }
};
static_assert(sizeof(Point) == 24);

/// Which optional per-point fields carry real data (the others hold defaults).
struct PointFields {
  bool intensity = false;
  bool ring = false;
  bool time = false;
  bool label = false;
  bool operator==(const PointFields&) const = default;
};

/// A set of points, usually one full sweep of a spinning sensor.
///
/// `labels` is either empty or holds one entry per point (SemanticKITTI layout: low 16 bits class,
/// high 16 bits instance). An organized cloud (a range image stored row-major, e.g. Ouster) has
/// `height > 1` and `width * height == size()`; an unorganized one has height 1.
struct PointCloud {
  std::vector<Point> points;
  std::vector<std::uint32_t> labels;
  PointFields fields;        ///< which optional fields are filled
  double stamp_s = 0.0;      ///< s, sweep start time (sensor or bag clock)
  std::uint32_t width = 0;   ///< points per row when organized, else size()
  std::uint32_t height = 1;  ///< rows when organized, else 1
  /// m: where this cloud's frame origin lies in a larger, usually georeferenced frame (a LAS
  /// file's projected coordinates): p_absolute = origin_m + p. Zero for sensor clouds. Points are
  /// kept relative to it so that float32 keeps millimetres where absolute UTM coordinates
  /// (~10^6 m) would keep only ~0.5 m.
  Eigen::Vector3d origin_m = Eigen::Vector3d::Zero();

  std::size_t size() const { return points.size(); }
  bool empty() const { return points.empty(); }
  void reserve(std::size_t n) { points.reserve(n); }
  void clear();
  /// Appends a point; keeps labels in step when the cloud is labelled.
  void push_back(const Point& p, std::uint32_t label = 0);
  bool is_organized() const { return height > 1 && std::size_t(width) * height == size(); }
  bool has_labels() const { return !labels.empty() && labels.size() == points.size(); }
  /// Number of distinct rings = 1 + largest ring index, 0 when no point has a ring.
  std::size_t ring_count() const;
  /// Number of points for which Point::is_valid() holds.
  std::size_t valid_count() const;
};

/// Axis-aligned bounds of the valid points (min > max when there is none).
struct Bounds3 {
  Eigen::Vector3d min{std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
                      std::numeric_limits<double>::max()};
  Eigen::Vector3d max{std::numeric_limits<double>::lowest(), std::numeric_limits<double>::lowest(),
                      std::numeric_limits<double>::lowest()};
  bool empty() const { return min.x() > max.x(); }
  void extend(const Eigen::Vector3d& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
};
Bounds3 compute_bounds(const PointCloud& cloud);

/// Keeps the points for which keep[i] is true (labels follow); the cloud becomes unorganized.
PointCloud select(const PointCloud& cloud, std::span<const bool> keep);

/// Drops the points nearer than `min_range_m` (3D) to the cloud's frame origin, the sensor (e.g.
/// the robot's own body), and those without a finite position, through select(); a range <= 0
/// leaves the cloud as it is.
void drop_nearer_than(PointCloud& cloud, double min_range_m);

}  // namespace fieldlidar
