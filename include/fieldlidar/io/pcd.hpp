#pragma once
/// \file PCD point clouds (PCL's format): ascii, binary and binary_compressed, read and write.

#include <cstddef>
#include <filesystem>
#include <span>
#include <string>

#include "fieldlidar/core/point_cloud.hpp"
#include "fieldlidar/io/file_util.hpp"

namespace fieldlidar::io {

/// Reads a PCD file. The header is parsed and checked against the file size before anything is
/// allocated; binary bodies are converted field by field in place (binary_compressed through
/// PCL's LZF decoder), ascii ones parsed strictly. Fields: x y z (required), intensity, ring,
/// label, and time (`t`, `time` offsets or an absolute `timestamp`: cloud.stamp_s = earliest stamp,
/// Point::time = offset, s). Organized clouds keep width x height; their NaN points become all-zero
/// no-returns. A VIEWPOINT without rotation is the cloud's origin_m (its translation; PCL's
/// VIEWPOINT is the pose of the cloud's frame). Throws fieldlidar::Error naming the file for a
/// missing file, a malformed or truncated header or body, or NaN coordinates in an unorganized
/// cloud.
PointCloud read_pcd(const std::filesystem::path& path);
/// The same from bytes held in memory (`source` names them in errors).
PointCloud parse_pcd(std::span<const std::byte> bytes, const std::string& source);

/// Writes x y z intensity [ring] [time | timestamp] [label], and cloud.origin_m (exactly, 17
/// digits) as the VIEWPOINT translation, so that a georeferenced cloud keeps its absolute position
/// (origin_m + p) while its points stay small float32s; options.binary / options.compressed choose
/// ascii, binary or binary_compressed. Refuses to replace a file unless options.overwrite.
void write_pcd(const std::filesystem::path& path, const PointCloud& cloud,
               const WriteOptions& options = {});

}  // namespace fieldlidar::io
