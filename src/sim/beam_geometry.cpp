// Where each beam of a sensor points and when it fires (the public beam-geometry functions of
// lidar_simulator.hpp).
#include <cmath>
#include <numbers>

#include "fieldlidar/sim/lidar_simulator.hpp"

namespace fieldlidar::sim {

double column_azimuth_rad(const SensorModel& sensor, int column) {
  const double res = sensor.horizontal_resolution_rad();
  if (sensor.kind != SensorModel::Kind::kSpinning)
    return -0.5 * sensor.horizontal_fov_rad + (column + 0.5) * res;  // right to left
  return std::numbers::pi - (column + 0.5) * res;                    // clockwise from behind
}

double firing_time_s(const SensorModel& sensor, int ring, int column) {
  const double period = sensor.sweep_period_s();
  if (sensor.kind != SensorModel::Kind::kSpinning) {
    constexpr double kTwoPi = 2 * std::numbers::pi;
    const double plane_period = period / double(sensor.rings());
    const double line_fraction = sensor.horizontal_fov_rad / kTwoPi;
    return plane_period * (ring + line_fraction * double(column) / sensor.columns);
  }
  return period * double(column) / sensor.columns;
}

Eigen::Vector3d beam_direction(const SensorModel& sensor, int ring, int column) {
  double az = column_azimuth_rad(sensor, column);
  const double el = sensor.beam_altitudes_rad[std::size_t(ring)];
  if (sensor.kind != SensorModel::Kind::kSpinning) {
    // The 2D scan plane is pitched up by `el` about the lidar's y axis (nodding scanner).
    return {std::cos(az) * std::cos(el), std::sin(az), std::cos(az) * std::sin(el)};
  }
  if (!sensor.beam_azimuth_offsets_rad.empty())
    az += sensor.beam_azimuth_offsets_rad[std::size_t(ring)];
  return {std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)};
}

}  // namespace fieldlidar::sim
