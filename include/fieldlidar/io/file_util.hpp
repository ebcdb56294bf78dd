#pragma once
/// \file Small file helpers shared by the readers and writers.

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace fieldlidar::io {

/// Whole file as bytes; throws fieldlidar::Error naming the file when it is missing or unreadable.
std::vector<std::byte> read_file_bytes(const std::filesystem::path& path);

/// Lower-case extension without the dot ("bin", "pcd", ...), "" when there is none.
std::string extension_of(const std::filesystem::path& path);

/// Throws fieldlidar::Error when `path` exists and `overwrite` is false, so that nothing the user
/// already has is replaced without being asked; also when its folder does not exist.
void check_writable(const std::filesystem::path& path, bool overwrite);

/// Writes `bytes` to `path` through a temporary file in the same folder and a rename, so a failed
/// write never leaves a half-written file where a good one was.
void write_file_atomic(const std::filesystem::path& path, const void* data, std::size_t size,
                       bool overwrite);

/// Options shared by all writers.
struct WriteOptions {
  bool overwrite = false;   ///< replace an existing file
  bool binary = true;       ///< binary encoding where the format has a choice (PCD, PLY)
  bool compressed = false;  ///< PCD binary_compressed
  /// Per-point time as `time` offsets from the sweep start (s) even when the cloud has a stamp
  /// (by default a cloud with stamp_s != 0 gets absolute `timestamp`s, one with stamp_s == 0
  /// offsets): one schema for every file of a sequence whose first stamp may be 0.
  bool time_offsets = false;
};

}  // namespace fieldlidar::io
