#include "fieldlidar/segmentation/ground.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "fieldlidar/core/error.hpp"
namespace fieldlidar::segmentation {

GroundResult segment_ground(const PointCloud& cloud, const SensorModel& sensor,
                            const GroundConfig& config) {
  // Far-flung coordinates would leave every point out of the sensor's reach (no ground, said
  // nowhere) or overflow the grid's cell indices.
  if (const auto why = implausible_span(cloud)) throw Error("ground: " + *why);
  switch (config.method) {
    case GroundMethod::kSeed000:
      return ground_seed000(cloud, sensor, config.seed000);
    case GroundMethod::kSeed002:
      return ground_seed002(cloud, sensor, config.seed002);
    case GroundMethod::kGrid:
      return ground_grid(cloud, config.grid);
    case GroundMethod::kRobust:
      break;
  }
  return ground_robust_levelled(cloud, sensor, config.robust, config.levelling);
}

}  // namespace fieldlidar::segmentation
