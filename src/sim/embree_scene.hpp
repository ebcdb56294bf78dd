#pragma once
// The static triangles of a scene in an Embree BVH, for the simulator's ray casting.

#include <embree3/rtcore.h>

#include <Eigen/Core>

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

/// A ray from `origin` along `dir` (not normalised here) up to `tfar`, with Embree's required
/// fields set: no hit yet, every geometry mask, no instance.
inline void set_ray(RTCRayHit& rh, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir,
                    float tfar, unsigned id) {
  rh.ray.org_x = float(origin.x());
  rh.ray.org_y = float(origin.y());
  rh.ray.org_z = float(origin.z());
  rh.ray.dir_x = float(dir.x());
  rh.ray.dir_y = float(dir.y());
  rh.ray.dir_z = float(dir.z());
  rh.ray.tnear = 0.f;
  rh.ray.tfar = tfar;
  rh.ray.time = 0.f;
  rh.ray.mask = ~0u;
  rh.ray.id = id;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}

}  // namespace fieldlidar::sim::detail
