#include "fieldlidar/segmentation/ground.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "fieldlidar/core/error.hpp"
namespace fieldlidar::segmentation {

GroundResult segment_ground(const PointCloud& cloud, const SensorModel& sensor,
                            const GroundConfig& config) {
  // The grid ground checks the span from the bounds it takes anyway.
  if (config.method == GroundMethod::kGrid) return ground_grid(cloud, config.grid);
  // Far-flung coordinates would leave every point out of the sensor's reach: no ground, said
  // nowhere.
  if (const auto why = implausible_span(cloud)) throw Error("ground: " + *why);
  switch (config.method) {
    case GroundMethod::kSeed000:
      return ground_seed000(cloud, sensor, config.seed000);
    case GroundMethod::kSeed002:
      return ground_seed002(cloud, sensor, config.seed002);
    case GroundMethod::kGrid:
    case GroundMethod::kRobust:
      break;
  }
  return ground_robust_levelled(cloud, sensor, config.robust, config.levelling);
}

}  // namespace fieldlidar::segmentation
