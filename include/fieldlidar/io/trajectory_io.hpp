#pragma once
/// \file Trajectory text files that `evo` reads: KITTI poses and TUM.
///
/// KITTI: one pose per line, the first three rows of the 4x4 matrix T_world_sensor row-major
/// (12 numbers), no times (an optional separate times file has one time in s per line).
/// TUM: `t x y z qx qy qz qw` per line (s, m, unit quaternion of T_world_sensor); `#` comments.

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "fieldlidar/core/pose.hpp"
#include "fieldlidar/io/file_util.hpp"

namespace fieldlidar::io {

/// Parses KITTI pose text. Stamps come from `stamps_s` (one per pose, increasing) or, when it is
/// empty, are the line index (0, 1, 2, ... s). Throws fieldlidar::Error naming `source` and the
/// line for a wrong number count, a non-number or NaN, or a rotation block that is not a rotation.
Trajectory parse_kitti_poses(std::string_view text, const std::string& source,
                             const std::vector<double>& stamps_s = {});
/// Reads a KITTI poses file and, when `times` is not empty, its KITTI times file (e.g. times.txt).
Trajectory read_kitti_poses(const std::filesystem::path& path,
                            const std::filesystem::path& times = {});
/// Parses / reads a KITTI times file: one time (s) per line.
std::vector<double> parse_kitti_times(std::string_view text, const std::string& source);
std::vector<double> read_kitti_times(const std::filesystem::path& path);
void write_kitti_poses(const std::filesystem::path& path, const Trajectory& trajectory,
                       const WriteOptions& options = {});
void write_kitti_times(const std::filesystem::path& path, const Trajectory& trajectory,
                       const WriteOptions& options = {});

/// Parses TUM text; the quaternion is normalised (a zero or non-finite one is an error).
Trajectory parse_tum(std::string_view text, const std::string& source);
Trajectory read_tum(const std::filesystem::path& path);
void write_tum(const std::filesystem::path& path, const Trajectory& trajectory,
               const WriteOptions& options = {});

}  // namespace fieldlidar::io
