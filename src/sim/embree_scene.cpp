#include "embree_scene.hpp"

#include <cstdint>
#include <stdexcept>

namespace fieldlidar::sim::detail {

void build_embree_scene(const TriangleMesh& mesh, EmbreeScene& out) {
  // Ray casting runs on the calling thread; one build thread keeps the shared machine quiet.
  out.device = rtcNewDevice("threads=1");
  if (!out.device) throw std::runtime_error("Embree: cannot create a device");
  out.scene = rtcNewScene(out.device);
  rtcSetSceneBuildQuality(out.scene, RTC_BUILD_QUALITY_HIGH);
  if (!mesh.empty()) {
    RTCGeometry geom = rtcNewGeometry(out.device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0,
                                                          RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                          mesh.vertices.size()));
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
      v[3 * i] = mesh.vertices[i].x();
      v[3 * i + 1] = mesh.vertices[i].y();
      v[3 * i + 2] = mesh.vertices[i].z();
    }
    auto* idx = static_cast<std::uint32_t*>(
        rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                3 * sizeof(std::uint32_t), mesh.triangles.size()));
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
      for (int k = 0; k < 3; ++k) idx[3 * i + k] = mesh.triangles[i][k];
    rtcSetGeometryBuildQuality(geom, RTC_BUILD_QUALITY_HIGH);
    rtcCommitGeometry(geom);
    rtcAttachGeometry(out.scene, geom);
    rtcReleaseGeometry(geom);
  }
  rtcCommitScene(out.scene);
  if (rtcGetDeviceError(out.device) != RTC_ERROR_NONE)
    throw std::runtime_error("Embree: building the scene failed");
}

}  // namespace fieldlidar::sim::detail
