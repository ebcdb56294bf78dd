// Builds against an installed fieldlidar: a sensor preset, a cloud, a KITTI round trip.
#include <cstdio>
#include <filesystem>

#include <fieldlidar/core.hpp>
#include <fieldlidar/io/cloud_file.hpp>

int main() {
  const auto vlp16 = fieldlidar::SensorModel::vlp16();
  fieldlidar::PointCloud cloud;
  for (std::size_t ring = 0; ring < vlp16.rings(); ++ring)
    cloud.push_back({10.f, 0.f, float(10.0 * std::tan(vlp16.beam_altitudes_rad[ring])), 1.f, 0.f,
                     static_cast<std::uint16_t>(ring)});
  const auto path = std::filesystem::temp_directory_path() / "fieldlidar_consumer.bin";
  fieldlidar::io::write_cloud(path, cloud, {.overwrite = true});
  const auto back = fieldlidar::io::read_cloud(path);
  std::filesystem::remove(path);
  std::printf("consumer: %zu beams, wrote and read %zu points\n", vlp16.rings(), back.size());
  return back.size() == cloud.size() ? 0 : 1;
}
