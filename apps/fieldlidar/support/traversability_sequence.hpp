#pragma once
// `fieldlidar traversability` on a sequence: every frame fused into one TerrainMap, placed by a
// poses file or by the lidar odometry, each sweep de-skewed to the next one's pose.

#include <cstddef>
#include <string>

#include "fieldlidar/core/grid2d.hpp"
#include "fieldlidar/core/pose.hpp"
#include "fieldlidar/terrain/traversability.hpp"

namespace fieldlidar::app {

struct SequenceOptions {
  std::string input;   ///< a folder, glob, pcap, bag or simulator folder
  std::string poses;   ///< KITTI (one pose per frame) or TUM (by stamp) file; "": lidar odometry
  std::string sensor;  ///< sensor preset when the frames do not say
  double min_range_m = 0;  ///< returns nearer the sensor dropped (the robot's body)
};

struct SequenceResult {
  Grid2D map;
  std::size_t frames = 0, skipped = 0, deskewed = 0;
  std::string placed_by, sensor;
  Trajectory path;
  double update_ms = 0;  ///< map updates only (segmentation included), summed
};

/// Every frame of a sequence fused into one map, placed by the poses file or else by the lidar
/// odometry (the first scan's frame). Throws fieldlidar::Error naming the input or the poses file
/// (poses of another sequence, no frame placed, a frame of implausible span).
SequenceResult map_sequence(const SequenceOptions& o, const terrain::TraversabilityConfig& cfg);

}  // namespace fieldlidar::app
