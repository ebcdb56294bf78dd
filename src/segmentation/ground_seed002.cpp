// seed 002, step b: ground from the downward beams, H - h <= 0.05 m.

#include "fieldlidar/segmentation/ground.hpp"
#include "polar_grid.hpp"

namespace fieldlidar::segmentation {

GroundResult ground_seed002(const PointCloud& cloud, const SensorModel& sensor,
                            const Seed002GroundConfig& config) {
  GroundResult result;
  result.is_ground.assign(cloud.size(), 0);
  double H = config.mounting_height_m;
  if (!(H > 0)) H = sensor.mounting_height_m;
  if (!(H > 0)) H = estimate_sensor_height(cloud, 12.0, 0.0);
  result.sensor_height_m = H;
  if (!(H > 0)) return result;  // no ground below the sensor to be found
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Point& p = cloud.points[i];
    // A downward beam hits below the sensor: z < 0 in the lidar frame. The drop h from the sensor
    // origin to the point is the vertical component of that vector, h = -z.
    if (!valid_point(p) || p.z >= 0.f) continue;
    const double h = -double(p.z);
    if (H - h <= config.tolerance_m) {
      result.is_ground[i] = 1;
      ++result.ground_count;
    }
  }
  return result;
}

}  // namespace fieldlidar::segmentation
