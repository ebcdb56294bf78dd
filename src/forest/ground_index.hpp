#pragma once
// Ground points binned in 1 m cells: the ground height near a stem's axis.
#include <cstdint>
#include <span>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>

#include "fieldlidar/core/point_cloud.hpp"

namespace fieldlidar::forest {

class GroundIndex {
 public:
  GroundIndex(const PointCloud& cloud, std::span<const std::uint8_t> is_ground);
  /// Median z of the ground points within radius of xy; NaN when there is none.
  double height_near(const Eigen::Vector2d& xy, double radius) const;
  /// z at quantile q (0..1) of the ground points within radius of xy; NaN when there is none.
  double quantile_near(const Eigen::Vector2d& xy, double radius, double q) const;
  /// Height at xy of the plane fitted (least squares) to the ground points within radius: the
  /// floor under a stem whose own foot is hidden (a shrub in front). NaN with fewer than
  /// min_points or when they do not span both horizontal directions.
  double plane_height_near(const Eigen::Vector2d& xy, double radius,
                           std::size_t min_points = 20) const;

 private:
  std::vector<Eigen::Vector3d> within(const Eigen::Vector2d& xy, double radius) const;
  static std::int64_t cell(double v);
  static std::int64_t key(std::int64_t x, std::int64_t y) { return (x << 32) ^ (y & 0xffffffff); }
  struct Range {
    std::uint32_t begin = 0, count = 0;  ///< in points_
  };
  std::unordered_map<std::int64_t, Range> cells_;
  std::vector<Eigen::Vector3d> points_;
};

}  // namespace fieldlidar::forest
