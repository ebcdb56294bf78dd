#pragma once
// The static triangles of a scene in an Embree BVH, for the simulator's ray casting.

#include <embree3/rtcore.h>

#include "fieldlidar/sim/mesh.hpp"

namespace fieldlidar::sim::detail {

/// Owns an Embree device and scene; releases both.
struct EmbreeScene {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  EmbreeScene() = default;
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;
  ~EmbreeScene() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

/// Creates the device (one thread) and builds a committed scene of `mesh`'s triangles (geometry
/// 0; a hit's primID indexes mesh.triangles and mesh.labels). Throws std::runtime_error when
/// Embree fails.
void build_embree_scene(const TriangleMesh& mesh, EmbreeScene& out);

}  // namespace fieldlidar::sim::detail
