// Ground height near a stem: median of the ground returns around it.
#include "ground_index.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Dense>

namespace fieldlidar::forest {

std::int64_t GroundIndex::cell(double v) {
  return std::int64_t(std::floor(v));
}

// The points of every cell in one array, cell after cell, each cell's in cloud order: two
// passes (count, then place) instead of a vector per cell.
GroundIndex::GroundIndex(const PointCloud& cloud, std::span<const std::uint8_t> is_ground) {
  const auto ground = [&](std::size_t i) { return is_ground[i] && cloud.points[i].is_valid(); };
  const auto key_of = [](const Point& p) { return key(cell(p.x), cell(p.y)); };
  std::size_t n = 0;
  for (std::size_t i = 0; i < is_ground.size(); ++i)
    if (ground(i)) ++cells_[key_of(cloud.points[i])].count, ++n;
  std::uint32_t begin = 0;
  for (auto& [k, range] : cells_) {
    range.begin = begin;
    begin += range.count;
    range.count = 0;
  }
  points_.resize(n);
  for (std::size_t i = 0; i < is_ground.size(); ++i)
    if (ground(i)) {
      auto& range = cells_[key_of(cloud.points[i])];
      points_[range.begin + range.count++] = cloud.points[i].xyz().cast<double>();
    }
}

double GroundIndex::height_near(const Eigen::Vector2d& xy, double radius) const {
  return quantile_near(xy, radius, 0.5);
}

std::vector<Eigen::Vector3d> GroundIndex::within(const Eigen::Vector2d& xy, double radius) const {
  std::vector<Eigen::Vector3d> out;
  const int r = int(std::ceil(radius));
  for (int dx = -r; dx <= r; ++dx)
    for (int dy = -r; dy <= r; ++dy) {
      auto it = cells_.find(key(cell(xy.x()) + dx, cell(xy.y()) + dy));
      if (it == cells_.end()) continue;
      const auto& range = it->second;
      for (std::uint32_t k = range.begin; k < range.begin + range.count; ++k)
        if ((points_[k].head<2>() - xy).norm() <= radius) out.push_back(points_[k]);
    }
  return out;
}

double GroundIndex::quantile_near(const Eigen::Vector2d& xy, double radius, double q) const {
  std::vector<double> z;
  for (const auto& p : within(xy, radius)) z.push_back(p.z());
  if (z.empty()) return std::numeric_limits<double>::quiet_NaN();
  const auto k = std::size_t(std::clamp(q, 0.0, 1.0) * double(z.size() - 1));
  std::nth_element(z.begin(), z.begin() + k, z.end());
  return z[k];
}

double GroundIndex::plane_height_near(const Eigen::Vector2d& xy, double radius,
                                      std::size_t min_points) const {
  const auto pts = within(xy, radius);
  if (pts.size() < min_points) return std::numeric_limits<double>::quiet_NaN();
  // z = a + b (x - x0) + c (y - y0), centred on xy so that a is the answer.
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (const auto& p : pts) {
    const Eigen::Vector3d row(1.0, p.x() - xy.x(), p.y() - xy.y());
    A += row * row.transpose();
    b += row * p.z();
  }
  // Points on one line (a single ring's arc) leave the tilt across it free.
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> spread(A.block<2, 2>(1, 1) / double(pts.size()) -
                                                        A.block<2, 1>(1, 0) * A.block<1, 2>(0, 1) /
                                                            std::pow(double(pts.size()), 2));
  if (spread.eigenvalues()(0) < 0.25) return std::numeric_limits<double>::quiet_NaN();
  return A.ldlt().solve(b)(0);
}

}  // namespace fieldlidar::forest
