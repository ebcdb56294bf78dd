#pragma once
/// \file Ray-cast LiDAR over a Scene: one full sweep per scan() call, the sensor moving during the
/// sweep exactly as given by T_world_lidar(t).

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "fieldlidar/core/point_cloud.hpp"
#include "fieldlidar/core/pose.hpp"
#include "fieldlidar/core/sensor_model.hpp"
#include "fieldlidar/sim/scene.hpp"

namespace fieldlidar::sim {

/// Order of the points in SimFrame::cloud.
enum class PointOrder {
  kRingMajor,    ///< ring 0 first, each ring in firing (azimuth) order
  kFiringOrder,  ///< column by column as the sensor fires, rings ascending within a column
};

struct SimConfig {
  double range_noise_m = -1.0;           ///< 1-sigma Gaussian range noise; < 0 uses the sensor's
  double dropout_probability = 0.0;      ///< chance that a return is lost at random
  double grazing_dropout_cos = 0.05;     ///< returns whose |cos(incidence)| is below this are lost
  bool intensity_from_incidence = true;  ///< intensity = 255 * reflectivity(class) * |cos(inc)|
  bool organized = false;  ///< keep every beam (rings x columns, no-return = all-zero point)
  PointOrder order = PointOrder::kRingMajor;
  bool simulate_people = true;
  std::uint64_t seed = 1;  ///< noise seed; each sweep's noise depends on (seed, t0)
};

struct SimFrame {
  /// Points in the lidar frame at each point's own firing time (skewed like a real sensor),
  /// ring, time (s from t0), intensity, labels (core/labels.hpp) filled.
  PointCloud cloud;
  double stamp_s = 0.0;                         ///< t0, sweep start
  Pose T_world_lidar_start = Pose::Identity();  ///< pose at t0
  Pose T_world_lidar_end = Pose::Identity();    ///< pose at t0 + sweep period
  std::vector<PersonTruth> people;              ///< truth at t0, with hit counts
};

/// Azimuth (rad, CCW from +x) of column `c` of a spinning sensor. Columns run clockwise seen from
/// above starting behind the sensor, like a Velodyne: c = 0 at +pi, c = columns/2 at 0 (forward).
double column_azimuth_rad(const SensorModel& sensor, int column);
/// Firing time (s from the sweep start) of (ring, column). Spinning: column/columns * period.
/// Tilting 2D: plane `ring` is scanned during [ring, ring+1) * period/planes, its beams over the
/// fraction fov/(2 pi) of that interval.
double firing_time_s(const SensorModel& sensor, int ring, int column);
/// Unit beam direction in the lidar frame.
Eigen::Vector3d beam_direction(const SensorModel& sensor, int ring, int column);

class LidarSimulator {
 public:
  /// Builds the ray-casting structure for the scene's static geometry (copies what it needs; the
  /// scene may be destroyed afterwards). Throws std::invalid_argument for an invalid sensor.
  LidarSimulator(const Scene& scene, const SensorModel& sensor, const SimConfig& config = {});
  ~LidarSimulator();
  LidarSimulator(LidarSimulator&&) noexcept;
  LidarSimulator& operator=(LidarSimulator&&) noexcept;

  /// One full sweep starting at t0_s; the sensor pose at each firing time t is T_world_lidar(t).
  SimFrame scan(double t0_s, const std::function<Pose(double)>& T_world_lidar) const;
  /// Same with a fixed pose (no motion during the sweep).
  SimFrame scan(double t0_s, const Pose& T_world_lidar) const;

  const SensorModel& sensor() const;
  const SimConfig& config() const;

  /// First static-geometry hit along a world ray: distance (m) and label, nullopt on a miss.
  struct Hit {
    double range_m;
    std::uint32_t label;
    Eigen::Vector3d normal;  ///< unit geometric normal, outward for closed meshes (CCW winding)
  };
  std::optional<Hit> cast(const Eigen::Vector3d& origin_m, const Eigen::Vector3d& direction,
                          double max_range_m) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace fieldlidar::sim
