#include "fieldlidar/segmentation/segment.hpp"

#include <algorithm>
#include <string>

#include "fieldlidar/core/error.hpp"
#include "polar_grid.hpp"

namespace fieldlidar::segmentation {

SegmentResult segment(const PointCloud& cloud, const SensorModel& sensor,
                      const SegmentConfig& config) {
  SegmentResult out;
  if (config.cluster_method == ClusterMethod::kRangeImage ||
      config.ground.method == GroundMethod::kSeed000) {
    // One image serves both steps of seed 000.
    const RangeImage image = RangeImage::build(cloud, sensor, config.image);
    out.ground = config.ground.method == GroundMethod::kSeed000
                     ? ground_seed000(cloud, image, config.ground.seed000)
                     : segment_ground(cloud, sensor, config.ground);
    out.clusters = config.cluster_method == ClusterMethod::kRangeImage
                       ? cluster_range_image(cloud, image, out.ground.is_ground, config.range_image)
                       : cluster_euclidean(cloud, out.ground.is_ground, config.euclidean);
    return out;
  }
  out.ground = segment_ground(cloud, sensor, config.ground);
  out.clusters = cluster_euclidean(cloud, out.ground.is_ground, config.euclidean);
  return out;
}

std::vector<std::uint32_t> segment_labels(const PointCloud& cloud, const SegmentResult& result) {
  std::vector<std::uint32_t> labels(cloud.size(), kLabelInvalid);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (!valid_point(cloud.points[i])) continue;
    if (i < result.ground.is_ground.size() && result.ground.is_ground[i])
      labels[i] = kLabelGround;
    else if (i < result.clusters.cluster_of_point.size() &&
             result.clusters.cluster_of_point[i] >= 0)
      labels[i] = kLabelClusterBase + std::uint32_t(result.clusters.cluster_of_point[i]);
    else
      labels[i] = kLabelUnclustered;
  }
  return labels;
}

GroundScore score_ground(const PointCloud& cloud, std::span<const std::uint8_t> is_ground,
                         std::span<const std::uint32_t> truth_labels,
                         std::span<const std::uint16_t> ground_classes,
                         std::span<const std::uint16_t> ignored_classes) {
  if (truth_labels.size() != cloud.size())
    throw Error("ground scoring: " + std::to_string(truth_labels.size()) + " truth labels for " +
                std::to_string(cloud.size()) + " points");
  if (is_ground.size() != cloud.size())
    throw Error("ground scoring: " + std::to_string(is_ground.size()) + " ground flags for " +
                std::to_string(cloud.size()) + " points");
  auto in = [](std::span<const std::uint16_t> set, std::uint16_t c) {
    return std::find(set.begin(), set.end(), c) != set.end();
  };
  GroundScore s;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (!valid_point(cloud.points[i])) continue;
    const auto cls = std::uint16_t(truth_labels[i] & 0xFFFFu);
    if (in(ignored_classes, cls)) continue;
    const bool truth = in(ground_classes, cls);
    const bool pred = is_ground[i] != 0;
    if (truth && pred)
      ++s.true_positive;
    else if (!truth && pred)
      ++s.false_positive;
    else if (truth && !pred)
      ++s.false_negative;
    else
      ++s.true_negative;
  }
  const double tp = double(s.true_positive);
  s.precision = tp + s.false_positive > 0 ? tp / (tp + s.false_positive) : 0.0;
  s.recall = tp + s.false_negative > 0 ? tp / (tp + s.false_negative) : 0.0;
  s.f1 = s.precision + s.recall > 0 ? 2 * s.precision * s.recall / (s.precision + s.recall) : 0.0;
  return s;
}

std::vector<std::uint16_t> semantickitti_ground_classes() {
  return {40, 44, 48, 49, 60, 72};
}
std::vector<std::uint16_t> semantickitti_ignored_classes() {
  return {0, 1};
}
std::vector<std::uint16_t> rellis_ground_classes() {
  return {1, 3, 10, 23, 31, 33};
}
std::vector<std::uint16_t> rellis_ignored_classes() {
  return {0};
}

}  // namespace fieldlidar::segmentation
