#include "fieldlidar/segmentation/range_image.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "fieldlidar/core/error.hpp"
#include "polar_grid.hpp"

namespace fieldlidar::segmentation {

int azimuth_column(double azimuth_rad, int columns) {
  // seed 000: col = round(atan2(y, x) / theta_horizon) + kscan_horizon / 2.
  const double theta_horizon = 2.0 * std::numbers::pi / columns;
  int col = static_cast<int>(std::lround(azimuth_rad / theta_horizon)) + columns / 2;
  col %= columns;
  if (col < 0) col += columns;
  return col;
}

RangeImage RangeImage::build(const PointCloud& cloud, const SensorModel& sensor,
                             const RangeImageConfig& config) {
  try {
    sensor.validate();
  } catch (const std::invalid_argument& e) {
    throw Error(std::string("range image: ") + e.what());
  }
  RangeImage img;
  img.rows = static_cast<int>(sensor.rings());
  img.cols = config.columns > 0 ? config.columns : sensor.columns;
  const std::size_t cells = std::size_t(img.rows) * img.cols;
  img.cell_point.assign(cells, -1);
  img.cell_range_m.assign(cells, 0.f);
  img.labels.assign(cells, CellLabel::kEmpty);
  img.point_cell.assign(cloud.size(), -1);
  img.row_altitude_rad.assign(sensor.beam_altitudes_rad.begin(), sensor.beam_altitudes_rad.end());

  RowSource source = config.row_source;
  if (source == RowSource::kAuto)
    source = cloud.fields.ring ? RowSource::kRingField : RowSource::kEstimated;
  if (source == RowSource::kRingField && !cloud.fields.ring)
    throw Error("range image: row source 'ring field' asked for, but the cloud has no ring field");

  std::vector<std::uint16_t> estimated;
  if (source == RowSource::kEstimated) estimated = estimate_rings(cloud, sensor).rings;

  // seed 000: row = (atan2(z, hypot(x, y)) + theta_bottom) / res_vertical.
  const double theta_bottom = -sensor.min_altitude_rad();
  const double res_vertical = sensor.vertical_resolution_rad();

  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Point& p = cloud.points[i];
    if (!valid_point(p)) continue;
    const float xy2 = p.x * p.x + p.y * p.y;
    const double xy = std::sqrt(double(xy2));
    const double range = std::sqrt(double(xy2) + double(p.z) * p.z);
    if (range <= 0.0) continue;
    int row = -1;
    switch (source) {
      case RowSource::kRingField:
        if (p.ring == Point::kNoRing) continue;
        if (p.ring >= img.rows)
          throw Error("range image: point " + std::to_string(i) + " has ring " +
                      std::to_string(p.ring) + " but sensor '" + sensor.name + "' has " +
                      std::to_string(img.rows) + " rings");
        row = p.ring;
        break;
      case RowSource::kElevation: {
        const double elevation = std::atan2(double(p.z), xy);
        row = res_vertical > 0
                  ? static_cast<int>(std::lround((elevation + theta_bottom) / res_vertical))
                  : 0;
        if (row < 0 || row >= img.rows) continue;  // outside the sensor's vertical field
        break;
      }
      case RowSource::kNearestBeam:
        row = static_cast<int>(sensor.nearest_ring(std::atan2(double(p.z), xy)));
        break;
      case RowSource::kEstimated:
      case RowSource::kAuto:
        if (estimated[i] == Point::kNoRing) continue;
        row = std::min<int>(estimated[i], img.rows - 1);
        break;
    }
    const int col = azimuth_column(std::atan2(p.y, p.x), img.cols);
    const std::int32_t cell = row * img.cols + col;
    img.point_cell[i] = cell;
    auto& kept = img.cell_point[cell];
    if (kept < 0) {
      kept = static_cast<std::int32_t>(i);
      img.cell_range_m[cell] = static_cast<float>(range);
      img.labels[cell] = CellLabel::kUnknown;
    } else {
      // seed 000: one point per cell; the nearer return wins since it occludes the other.
      ++img.duplicates;
      if (range < img.cell_range_m[cell]) {
        kept = static_cast<std::int32_t>(i);
        img.cell_range_m[cell] = static_cast<float>(range);
      }
    }
  }
  return img;
}

}  // namespace fieldlidar::segmentation
