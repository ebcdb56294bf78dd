// seed 002, steps a-c: rings, ground and noise clusters, reusing segmentation/.

#include "fieldlidar/odometry/preprocess.hpp"

#include <cmath>

#include "fieldlidar/segmentation/range_image.hpp"

namespace fieldlidar::odometry {

void correct_elevation(PointCloud& cloud, double angle_rad) {
  const float c = float(std::cos(angle_rad)), s = float(std::sin(angle_rad));
  for (auto& p : cloud.points) {
    if (!p.is_valid()) continue;
    const float h = std::hypot(p.x, p.y);
    if (h <= 0.f) continue;
    const float h2 = h * c - p.z * s;  // (h, z) turned by the angle in the vertical plane
    p.z = h * s + p.z * c;
    p.x *= h2 / h;
    p.y *= h2 / h;
  }
}

Preprocessed preprocess(const PointCloud& cloud, const SensorModel& sensor,
                        const PreprocessConfig& config) {
  Preprocessed out;
  if (cloud.fields.ring) {
    out.rings.resize(cloud.size());
    for (std::size_t i = 0; i < cloud.size(); ++i)
      out.rings[i] = cloud.points[i].is_valid() ? cloud.points[i].ring : Point::kNoRing;
  } else {
    out.rings = segmentation::estimate_rings(cloud, sensor).rings;
  }
  if (config.split_ground || config.drop_small_clusters)
    out.ground = segmentation::segment_ground(cloud, sensor, config.ground).is_ground;
  if (config.drop_small_clusters) {
    const auto clusters = segmentation::cluster_euclidean(cloud, out.ground, config.clusters);
    out.allowed.assign(cloud.size(), 1);
    for (std::size_t i = 0; i < cloud.size(); ++i)
      if (!out.ground[i] && clusters.cluster_of_point[i] < 0) out.allowed[i] = 0;
  }
  if (!config.split_ground) out.ground.clear();
  return out;
}

}  // namespace fieldlidar::odometry
