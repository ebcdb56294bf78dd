#include "fieldlidar/io/kitti_bin.hpp"

#include <cmath>
#include <cstring>
#include <vector>

#include "fieldlidar/core/error.hpp"

namespace fieldlidar::io {

PointCloud parse_kitti_bin(std::span<const std::byte> bytes, const std::string& source) {
  constexpr std::size_t kStride = 4 * sizeof(float);
  if (bytes.size() % kStride != 0)
    throw Error(source + ": KITTI .bin size " + std::to_string(bytes.size()) +
                " bytes is not a multiple of 16 (float32 x y z intensity); truncated or not a "
                "KITTI scan");
  const std::size_t n = bytes.size() / kStride;
  PointCloud cloud;
  cloud.points.resize(n);
  cloud.fields.intensity = true;
  cloud.width = static_cast<std::uint32_t>(n);
  for (std::size_t i = 0; i < n; ++i) {
    float v[4];
    std::memcpy(v, bytes.data() + i * kStride, kStride);
    if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2]))
      throw Error(source + ": point " + std::to_string(i) + " has a NaN or infinite coordinate");
    Point& p = cloud.points[i];
    p.x = v[0];
    p.y = v[1];
    p.z = v[2];
    p.intensity = std::isfinite(v[3]) ? v[3] : 0.f;
  }
  return cloud;
}

PointCloud read_kitti_bin(const std::filesystem::path& path) {
  const auto bytes = read_file_bytes(path);
  return parse_kitti_bin(bytes, path.string());
}

void write_kitti_bin(const std::filesystem::path& path, const PointCloud& cloud,
                     const WriteOptions& options) {
  std::vector<float> data(cloud.size() * 4);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Point& p = cloud.points[i];
    data[4 * i + 0] = p.x;
    data[4 * i + 1] = p.y;
    data[4 * i + 2] = p.z;
    data[4 * i + 3] = p.intensity;
  }
  write_file_atomic(path, data.data(), data.size() * sizeof(float), options.overwrite);
}

}  // namespace fieldlidar::io
