#pragma once
/// \file KITTI Velodyne `.bin` scans: float32 x y z intensity per point, no header.

#include <cstddef>
#include <filesystem>
#include <span>
#include <string>

#include "fieldlidar/core/point_cloud.hpp"
#include "fieldlidar/io/file_util.hpp"

namespace fieldlidar::io {

/// Parses KITTI `.bin` bytes. `source` names the input in error messages. All-zero points (the
/// "no return" entries of organized exports such as RELLIS-3D) are kept so that point indices stay
/// aligned with a `.label` file. Throws fieldlidar::Error when the size is not a multiple of 16
/// bytes or a coordinate is NaN/Inf.
PointCloud parse_kitti_bin(std::span<const std::byte> bytes, const std::string& source);
PointCloud read_kitti_bin(const std::filesystem::path& path);
void write_kitti_bin(const std::filesystem::path& path, const PointCloud& cloud,
                     const WriteOptions& options = {});

}  // namespace fieldlidar::io
