#pragma once
/// \file PLY point clouds (vertex element only): ascii and binary, read and write, via PCL.

#include <filesystem>
#include <string>

#include "fieldlidar/core/point_cloud.hpp"
#include "fieldlidar/io/file_util.hpp"

namespace fieldlidar::io {

/// Reads the vertex element of a PLY file: x y z (required), intensity (also `scalar_intensity`),
/// ring, label, time offsets or an absolute timestamp, mapped as for PCD. The header is checked
/// against the file size before PCL's PLYReader decodes it. Throws fieldlidar::Error naming the
/// file for a missing file, a wrong magic, a malformed or truncated file, or NaN coordinates.
/// A header line `comment fieldlidar origin_m X Y Z` gives the cloud's origin_m (m).
PointCloud read_ply(const std::filesystem::path& path);

/// The cloud as the bytes of a PLY file: x y z intensity ... as for PCD (io/pcl_fields), binary
/// little-endian or ascii (float32 with 9 significant digits, float64 with 17: both round-trip); a
/// non-zero cloud.origin_m goes into the header as `comment fieldlidar origin_m X Y Z` (17
/// digits: exact), so that a georeferenced cloud keeps its absolute position (origin_m + p).
/// time_offsets: write per-point time as offsets from the sweep start (see WriteOptions).
std::string encode_ply(const PointCloud& cloud, bool binary, bool time_offsets = false);

/// Writes the cloud as PLY vertices (binary little-endian unless options.binary is false) through
/// write_file_atomic: a failed write throws and leaves no file.
void write_ply(const std::filesystem::path& path, const PointCloud& cloud,
               const WriteOptions& options = {});

}  // namespace fieldlidar::io
