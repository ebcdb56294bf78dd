// Builds against an installed fieldlidar: a sensor preset, a synthetic sweep written to PCD, read
// back through FrameSource and segmented into ground and objects.
#include <cmath>
#include <cstdio>
#include <filesystem>

#include <fieldlidar/core.hpp>
#include <fieldlidar/io/cloud_file.hpp>
#include <fieldlidar/io/frame_source.hpp>
#include <fieldlidar/segmentation/segment.hpp>

int main() {
  using namespace fieldlidar;
  const SensorModel lidar = SensorModel::vlp16();
  // A flat ground 1 m below the sensor and a 0.5 m wide post 6 m ahead.
  PointCloud cloud;
  cloud.fields.ring = true;
  for (std::size_t ring = 0; ring < lidar.rings(); ++ring) {
    const double alt = lidar.beam_altitudes_rad[ring];
    for (int col = 0; col < lidar.columns; ++col) {
      const double az = col * lidar.horizontal_resolution_rad();
      double range = alt < 0 ? 1.0 / std::tan(-alt) / std::cos(alt) : 0.0;
      const bool post = std::abs(std::remainder(az, 2 * M_PI)) < 0.04;
      if (post && (range == 0.0 || range > 6.0)) range = 6.0 / std::cos(alt);
      if (range <= 0.0 || range > 60.0) continue;
      cloud.push_back({float(range * std::cos(alt) * std::cos(az)),
                       float(range * std::cos(alt) * std::sin(az)), float(range * std::sin(alt)),
                       1.f, 0.f, static_cast<std::uint16_t>(ring)});
    }
  }
  const auto path = std::filesystem::temp_directory_path() / "fieldlidar_consumer.pcd";
  io::write_cloud(path, cloud, {.overwrite = true});
  auto source = io::FrameSource::open(path);
  int objects = -1;
  while (auto frame = source->next()) {
    const auto seg = segmentation::segment(frame->cloud, lidar);
    objects = static_cast<int>(seg.clusters.clusters.size());
    for (const auto& c : seg.clusters.clusters)
      std::printf("consumer: object of %zu points at (%.1f, %.1f) m\n", c.indices.size(),
                  c.centroid.x(), c.centroid.y());
  }
  std::filesystem::remove(path);
  std::printf("consumer: %zu points, %d object(s)\n", cloud.size(), objects);
  return objects == 1 ? 0 : 1;
}
