#pragma once
/// \file Ground + clusters in one call, and the per-point label file values of `fieldlidar
/// segment`.

#include <cstdint>
#include <vector>

#include "fieldlidar/segmentation/clustering.hpp"
#include "fieldlidar/segmentation/ground.hpp"

namespace fieldlidar::segmentation {

/// Values of the segment label file (one uint32 per input point).
inline constexpr std::uint32_t kLabelInvalid = 0;  ///< no return or invalid point
inline constexpr std::uint32_t kLabelGround = 1;
inline constexpr std::uint32_t kLabelUnclustered = 2;    ///< non-ground, in no cluster
inline constexpr std::uint32_t kLabelClusterBase = 100;  ///< 100 + k for cluster k

enum class ClusterMethod { kEuclidean, kRangeImage };

struct SegmentConfig {
  GroundConfig ground;
  ClusterMethod cluster_method = ClusterMethod::kEuclidean;
  EuclideanClusterConfig euclidean;
  RangeImageClusterConfig range_image;
  RangeImageConfig image;
};

struct SegmentResult {
  GroundResult ground;
  ClusterResult clusters;
};

SegmentResult segment(const PointCloud& cloud, const SensorModel& sensor,
                      const SegmentConfig& config = {});

/// Label file values for a segmentation of `cloud`.
std::vector<std::uint32_t> segment_labels(const PointCloud& cloud, const SegmentResult& result);

/// Ground truth scoring: precision, recall and F1 of ground flags against class labels.
struct GroundScore {
  std::size_t true_positive = 0, false_positive = 0, false_negative = 0, true_negative = 0;
  double precision = 0, recall = 0, f1 = 0;
};
/// Scores points whose label class is not in `ignored_classes` and that are valid returns;
/// `ground_classes` are the classes counted as ground.
GroundScore score_ground(const PointCloud& cloud, std::span<const std::uint8_t> is_ground,
                         std::span<const std::uint32_t> truth_labels,
                         std::span<const std::uint16_t> ground_classes,
                         std::span<const std::uint16_t> ignored_classes);
/// Class ids: SemanticKITTI ground = road 40, parking 44, sidewalk 48, other-ground 49, terrain 72,
/// lane-marking 60; ignored = unlabeled 0, outlier 1. RELLIS-3D ground = dirt 1, grass 3,
/// asphalt 10, concrete 23, puddle 31, mud 33; ignored = void 0.
std::vector<std::uint16_t> semantickitti_ground_classes();
std::vector<std::uint16_t> semantickitti_ignored_classes();
std::vector<std::uint16_t> rellis_ground_classes();
std::vector<std::uint16_t> rellis_ignored_classes();

}  // namespace fieldlidar::segmentation
