// Ground height near a stem: median of the ground returns around it.
#include "ground_index.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fieldlidar::forest {

std::int64_t GroundIndex::cell(double v) {
  return std::int64_t(std::floor(v));
}

GroundIndex::GroundIndex(const PointCloud& cloud, std::span<const std::uint8_t> is_ground) {
  for (std::size_t i = 0; i < is_ground.size(); ++i)
    if (is_ground[i] && cloud.points[i].is_valid()) {
      const auto& p = cloud.points[i];
      cells_[key(cell(p.x), cell(p.y))].push_back(p.xyz().cast<double>());
    }
}

double GroundIndex::height_near(const Eigen::Vector2d& xy, double radius) const {
  return quantile_near(xy, radius, 0.5);
}

double GroundIndex::quantile_near(const Eigen::Vector2d& xy, double radius, double q) const {
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
  const auto k = std::size_t(std::clamp(q, 0.0, 1.0) * double(z.size() - 1));
  std::nth_element(z.begin(), z.begin() + k, z.end());
  return z[k];
}

}  // namespace fieldlidar::forest
