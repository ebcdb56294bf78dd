// seed 000, step 2: ground by the height difference between neighbouring rows of the range image.

#include <cmath>
#include <numbers>

#include "fieldlidar/segmentation/ground.hpp"

namespace fieldlidar::segmentation {

GroundResult ground_seed000(const PointCloud& cloud, const SensorModel& sensor,
                            const Seed000GroundConfig& config) {
  const RangeImage image = RangeImage::build(cloud, sensor, config.image);
  GroundResult result = ground_seed000(cloud, image, config);
  return result;
}

GroundResult ground_seed000(const PointCloud& cloud, const RangeImage& image,
                            const Seed000GroundConfig& config) {
  GroundResult result;
  result.is_ground.assign(cloud.size(), 0);
  std::vector<std::uint8_t> cell_ground(image.cell_point.size(), 0);
  const double tan_slope = std::tan(config.max_slope_deg * std::numbers::pi / 180.0);
  const double tan_elev = std::tan(config.max_elevation_deg * std::numbers::pi / 180.0);
  double height_sum = 0;
  std::size_t height_n = 0;
  for (int c = 0; c < image.cols; ++c) {
    // Walk up each column from the lowest beam; rows are compared pairwise, skipping empty cells
    // (a missing return does not break the ground).
    int lower = -1;
    for (int r = 0; r < image.rows; ++r) {
      const std::int32_t idx = image.at(r, c);
      if (idx < 0) continue;
      const Point& p = cloud.points[idx];
      const double xy = std::hypot(double(p.x), double(p.y));
      if (double(p.z) > tan_elev * xy) break;  // above max_elevation_deg: no more ground
      if (lower >= 0) {
        const Point& q = cloud.points[lower];
        const double dz = std::abs(double(p.z) - double(q.z));
        const double dxy = std::hypot(double(p.x) - q.x, double(p.y) - q.y);
        if (dz <= config.max_height_step_m + tan_slope * dxy) {
          cell_ground[image.point_cell[lower]] = 1;
          cell_ground[image.point_cell[idx]] = 1;
        }
      }
      lower = idx;
    }
  }
  // Points that lost their cell to a nearer duplicate take the label of the cell's point.
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const std::int32_t cell = image.point_cell[i];
    if (cell >= 0 && cell_ground[cell]) {
      result.is_ground[i] = 1;
      ++result.ground_count;
      if (image.cell_point[cell] == std::int32_t(i) &&
          std::hypot(cloud.points[i].x, cloud.points[i].y) < 12.f) {
        height_sum -= cloud.points[i].z;
        ++height_n;
      }
    }
  }
  result.sensor_height_m = height_n ? height_sum / double(height_n) : 0.0;
  return result;
}

}  // namespace fieldlidar::segmentation
