#pragma once
/// \file A person has a body above the legs: of the leg pairs of a 3D sweep, those with returns
/// at torso height above them and none above a head's height. Leg-shaped pairs are everywhere in
/// a street or a yard (posts, bicycle racks, table and car parts, tree trunks, wall corners); a
/// post or a trunk goes on above a person's head, a rack or a bumper stops below the chest.
/// Each test applies only where the sensor's beams cross its band at the pair's range (a low
/// mower LiDAR does not see a chest 2 m away: there the torso is not asked for).

#include <span>
#include <vector>

#include <Eigen/Core>

#include "fieldlidar/core/point_cloud.hpp"
#include "fieldlidar/core/sensor_model.hpp"
#include "fieldlidar/people/leg_detector.hpp"

namespace fieldlidar::people {

struct BodyCheckConfig {
  bool enabled = true;
  double radius_m = 0.35;  ///< around the pair's midpoint (a body's half width)
  /// Torso band above the ground (m): returns on at least torso_min_rings rings, when that many
  /// of the sensor's beams cross the band at the pair's range.
  double torso_min_m = 1.1;
  double torso_max_m = 1.8;
  int torso_min_rings = 2;
  /// ... and on at least this fraction of those beams: a body within radius_m covers the band on
  /// nearly every beam that crosses it, while the top edge of a car door, a bumper or a box
  /// about 1.1-1.3 m high shows on a few (KITTI tracking 0000: false persons 2-7 rings of 9-23
  /// crossing beams, the pedestrian 10-12 of 11-12, the cyclist 14-20 of 15-21).
  double torso_ring_fraction = 0.6;
  /// Band above the head (m): no return there (checked where any beam crosses it).
  double clear_min_m = 2.1;
  double clear_max_m = 3.5;
};

/// Per person of `people` (positions in the frame of `cloud`, the sensor at its origin and the
/// ground `sensor_height_m` below it): 1 when it has a person's body by the rules above, 0 when
/// not. All 1 when the check is off. `cloud` needs its ring field (rings as in `sensor`).
/// `level_from_lidar`: the rotation that levelled `cloud` from the sensor's frame (a pitched or
/// rolled sensor's beams cross the bands at other heights).
std::vector<char> person_bodies(
    const PointCloud& cloud, const SensorModel& sensor, double sensor_height_m,
    std::span<const Person> people, const BodyCheckConfig& config = {},
    const Eigen::Matrix3d& level_from_lidar = Eigen::Matrix3d::Identity());

}  // namespace fieldlidar::people
