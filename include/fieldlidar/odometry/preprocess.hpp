#pragma once
/// \file seed 002, steps a-c before the features: rings, the ground split and the Euclidean
/// clusters that drop noise, all from segmentation/.

#include <cstdint>
#include <vector>

#include "fieldlidar/core/point_cloud.hpp"
#include "fieldlidar/core/sensor_model.hpp"
#include "fieldlidar/segmentation/clustering.hpp"
#include "fieldlidar/segmentation/ground.hpp"

namespace fieldlidar::odometry {

/// seed 002's ground (H - h <= 0.05 m on the downward beams).
inline segmentation::GroundConfig seed002_ground() {
  segmentation::GroundConfig g;
  g.method = segmentation::GroundMethod::kSeed002;
  return g;
}

struct PreprocessConfig {
  /// Added to every point's elevation angle (deg), range and azimuth kept. The KITTI HDL-64E
  /// clouds carry an intrinsic calibration error that bends the scan and makes LiDAR odometry's
  /// scale short: IMLS-SLAM (Deschaud 2018) corrects it with 0.22 deg, KISS-ICP with 0.205 deg.
  /// 0 = off (every other sensor).
  double elevation_correction_deg = 0.0;
  bool split_ground = false;  ///< ground points may only be planar features
  segmentation::GroundConfig ground = seed002_ground();
  bool drop_small_clusters = false;  ///< non-ground points in clusters of <= 20 points dropped
  segmentation::EuclideanClusterConfig clusters;
};

struct Preprocessed {
  std::vector<std::uint16_t> rings;   ///< per point (Point::kNoRing = none)
  std::vector<std::uint8_t> allowed;  ///< per point, 0 = noise (empty = all allowed)
  std::vector<std::uint8_t> ground;   ///< per point, 1 = ground (empty = none)
};

/// Every valid point turned up by `angle_rad` about the horizontal axis across its azimuth.
void correct_elevation(PointCloud& cloud, double angle_rad);

/// seed 002, step a (rings: the cloud's ring field, else estimated from scan order / elevation),
/// step b (ground) and step c (clusters of <= 20 points are noise).
Preprocessed preprocess(const PointCloud& cloud, const SensorModel& sensor,
                        const PreprocessConfig& config);

}  // namespace fieldlidar::odometry
