#include "fieldlidar/io/cloud_file.hpp"

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/kitti_bin.hpp"
#include "fieldlidar/io/las.hpp"
#include "fieldlidar/io/pcd.hpp"
#include "fieldlidar/io/ply.hpp"

namespace fieldlidar::io {

std::optional<CloudFormat> cloud_format_of(const std::filesystem::path& path) {
  const auto ext = extension_of(path);
  if (ext == "bin") return CloudFormat::kKittiBin;
  if (ext == "pcd") return CloudFormat::kPcd;
  if (ext == "ply") return CloudFormat::kPly;
  // .laz maps to LAS so that reading it gives the "decompress it first" error, not "unknown type".
  if (ext == "las" || ext == "laz") return CloudFormat::kLas;
  return std::nullopt;
}

std::string to_string(CloudFormat format) {
  switch (format) {
    case CloudFormat::kKittiBin:
      return "kitti-bin";
    case CloudFormat::kPcd:
      return "pcd";
    case CloudFormat::kPly:
      return "ply";
    case CloudFormat::kLas:
      return "las";
  }
  return "unknown";
}

namespace {
[[noreturn]] void unsupported(const std::filesystem::path& path) {
  throw Error(path.string() + ": unsupported file type '" + path.extension().string() +
              "' (expected .bin, .pcd, .ply or .las)");
}
}  // namespace

PointCloud read_cloud(const std::filesystem::path& path) {
  const auto format = cloud_format_of(path);
  if (!format) unsupported(path);
  switch (*format) {
    case CloudFormat::kKittiBin:
      return read_kitti_bin(path);
    case CloudFormat::kPcd:
      return read_pcd(path);
    case CloudFormat::kPly:
      return read_ply(path);
    case CloudFormat::kLas:
      return read_las(path).cloud;
  }
  unsupported(path);
}

void write_cloud(const std::filesystem::path& path, const PointCloud& cloud,
                 const WriteOptions& options) {
  const auto format = cloud_format_of(path);
  if (!format) unsupported(path);
  switch (*format) {
    case CloudFormat::kKittiBin:
      return write_kitti_bin(path, cloud, options);
    case CloudFormat::kPcd:
      return write_pcd(path, cloud, options);
    case CloudFormat::kPly:
      return write_ply(path, cloud, options);
    case CloudFormat::kLas:
      throw Error(path.string() + ": writing LAS is not supported (write .pcd, .ply or .bin)");
  }
  unsupported(path);
}

}  // namespace fieldlidar::io
