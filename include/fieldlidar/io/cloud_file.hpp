#pragma once
/// \file Reading and writing single-scan files, format chosen by extension.

#include <filesystem>
#include <optional>
#include <string>

#include "fieldlidar/core/point_cloud.hpp"
#include "fieldlidar/io/file_util.hpp"

namespace fieldlidar::io {

enum class CloudFormat { kKittiBin, kPcd, kPly, kLas };

/// Format from the file's extension (.bin, .pcd, .ply, .las); nullopt when not a cloud file.
std::optional<CloudFormat> cloud_format_of(const std::filesystem::path& path);
std::string to_string(CloudFormat format);

/// Reads one cloud; throws fieldlidar::Error naming the file and the problem (missing, truncated,
/// wrong magic, unsupported variant such as compressed LAZ, NaN coordinates).
PointCloud read_cloud(const std::filesystem::path& path);

/// Writes one cloud in the format of the extension; refuses to replace an existing file unless
/// options.overwrite is set.
void write_cloud(const std::filesystem::path& path, const PointCloud& cloud,
                 const WriteOptions& options = {});

}  // namespace fieldlidar::io
