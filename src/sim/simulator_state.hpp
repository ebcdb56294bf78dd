#pragma once
// The state of a LidarSimulator: the scene's BVH and moving people, and the sensor's beams in
// firing order.

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "embree_scene.hpp"
#include "fieldlidar/sim/heightfield.hpp"
#include "fieldlidar/sim/lidar_simulator.hpp"
#include "fieldlidar/sim/walker.hpp"

namespace fieldlidar::sim {

namespace detail {

/// One beam of the sensor: (ring, column), lidar-frame direction and origin, firing time after
/// the sweep start.
struct SimBeam {
  std::uint16_t ring;
  std::uint32_t column;
  float time_s;
  Eigen::Vector3f dir;
  Eigen::Vector3f origin;
};

/// Every beam of `sensor`, sorted by firing time (stable: column-major, rings ascending, among
/// beams that fire together).
std::vector<SimBeam> beams_in_firing_order(const SensorModel& sensor);

}  // namespace detail

struct LidarSimulator::Impl {
  detail::EmbreeScene embree;
  SensorModel sensor;
  SimConfig config;
  std::vector<std::uint32_t> labels;  // per static triangle
  std::vector<Walker> walkers;
  HeightField ground;
  std::vector<detail::SimBeam> beams;  // in firing order

  /// The bodies of every walker at time t, standing on the ground.
  std::vector<PersonBody> bodies_at(double t) const {
    std::vector<PersonBody> out;
    out.reserve(walkers.size());
    for (const auto& w : walkers) {
      Eigen::Vector2d xy, dir;
      w.path_point(w.arc_length_at(t), xy, dir);
      out.push_back(w.body_at(t, ground.height_at(xy)));
    }
    return out;
  }
};

}  // namespace fieldlidar::sim
