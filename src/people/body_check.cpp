// Leg pairs with a body above them (people::person_bodies).
#include "fieldlidar/people/body_check.hpp"

#include <algorithm>
#include <cmath>
#include <set>

namespace fieldlidar::people {
namespace {

// Beams of `sensor` that pass between heights lo and hi above the ground at `at` (level frame):
// each beam's elevation there after the sensor's tilt (`level_from_lidar`).
int beams_crossing(const SensorModel& sensor, const Eigen::Matrix3d& level_from_lidar,
                   double sensor_height_m, const Eigen::Vector2d& at, double lo, double hi) {
  const double r = at.norm();
  const Eigen::Vector3d toward = level_from_lidar.transpose() * Eigen::Vector3d(at.x(), at.y(), 0);
  const double azimuth = std::atan2(toward.y(), toward.x());
  int n = 0;
  for (const double a : sensor.beam_altitudes_rad) {
    const Eigen::Vector3d d =
        level_from_lidar * Eigen::Vector3d(std::cos(a) * std::cos(azimuth),
                                           std::cos(a) * std::sin(azimuth), std::sin(a));
    const double z = sensor_height_m + r * d.z() / std::max(1e-9, d.head<2>().norm());
    n += z >= lo && z <= hi;
  }
  return n;
}

}  // namespace

std::vector<char> person_bodies(const PointCloud& cloud, const SensorModel& sensor,
                                double sensor_height_m, std::span<const Person> people,
                                const BodyCheckConfig& c, const Eigen::Matrix3d& level_from_lidar) {
  std::vector<char> ok(people.size(), 1);
  if (!c.enabled || people.empty()) return ok;
  // The returns that can matter: between the torso band's foot and the top of the clear band.
  struct Band {
    Eigen::Vector2d xy;
    double above;
    int ring;
  };
  std::vector<Band> band;
  for (const auto& p : cloud.points) {
    if (!p.is_valid()) continue;
    const double above = double(p.z) + sensor_height_m;
    if (above >= c.torso_min_m && above <= c.clear_max_m)
      band.push_back({{p.x, p.y}, above, int(p.ring)});
  }
  const double r2 = c.radius_m * c.radius_m;
  for (std::size_t k = 0; k < people.size(); ++k) {
    const Eigen::Vector2d at = people[k].position_m;
    std::set<int> torso_rings;
    bool head_clear = true;
    for (const auto& b : band) {
      if ((b.xy - at).squaredNorm() > r2) continue;
      if (b.above <= c.torso_max_m) torso_rings.insert(b.ring);
      if (b.above >= c.clear_min_m) head_clear = false;
    }
    const int torso_beams =
        beams_crossing(sensor, level_from_lidar, sensor_height_m, at, c.torso_min_m, c.torso_max_m);
    const int rings_needed = std::max(
        c.torso_min_rings, int(std::ceil(c.torso_ring_fraction * double(torso_beams) - 1e-9)));
    const bool torso_seen =
        torso_beams < c.torso_min_rings || int(torso_rings.size()) >= rings_needed;
    ok[k] = torso_seen && head_clear;
  }
  return ok;
}

}  // namespace fieldlidar::people
