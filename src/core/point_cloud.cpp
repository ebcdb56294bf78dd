#include "fieldlidar/core/point_cloud.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <span>
#include <stdexcept>

namespace fieldlidar {

void PointCloud::clear() {
  points.clear();
  labels.clear();
  width = 0;
  height = 1;
}

void PointCloud::push_back(const Point& p, std::uint32_t label) {
  if (!labels.empty() || fields.label) labels.push_back(label);
  points.push_back(p);
  width = static_cast<std::uint32_t>(points.size());
  height = 1;
}

std::size_t PointCloud::ring_count() const {
  int max_ring = -1;
  for (const auto& p : points)
    if (p.ring != Point::kNoRing) max_ring = std::max<int>(max_ring, p.ring);
  return static_cast<std::size_t>(max_ring + 1);
}

std::size_t PointCloud::valid_count() const {
  return static_cast<std::size_t>(
      std::count_if(points.begin(), points.end(), [](const Point& p) { return p.is_valid(); }));
}

Bounds3 compute_bounds(const PointCloud& cloud) {
  Bounds3 b;
  for (const auto& p : cloud.points)
    if (p.is_valid()) b.extend(Eigen::Vector3d(p.x, p.y, p.z));
  return b;
}

PointCloud select(const PointCloud& cloud, std::span<const bool> keep) {
  if (keep.size() != cloud.size())
    throw std::invalid_argument("select: mask has " + std::to_string(keep.size()) +
                                " entries for a cloud of " + std::to_string(cloud.size()));
  PointCloud out;
  out.fields = cloud.fields;
  out.stamp_s = cloud.stamp_s;
  out.origin_m = cloud.origin_m;
  const bool labelled = cloud.has_labels();
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (!keep[i]) continue;
    out.points.push_back(cloud.points[i]);
    if (labelled) out.labels.push_back(cloud.labels[i]);
  }
  out.width = static_cast<std::uint32_t>(out.points.size());
  out.height = 1;
  return out;
}

void drop_nearer_than(PointCloud& cloud, double min_range_m) {
  if (!(min_range_m > 0.0)) return;
  const auto keep = std::make_unique<bool[]>(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i)
    keep[i] = cloud.points[i].xyz().cast<double>().norm() >= min_range_m;
  cloud = select(cloud, std::span<const bool>(keep.get(), cloud.size()));
}

}  // namespace fieldlidar
