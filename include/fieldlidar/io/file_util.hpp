#pragma once
/// \file Small file helpers shared by the readers and writers. Every file fieldlidar writes goes
/// through check_writable (before the work) and write_file_atomic (the bytes), so that no writer
/// replaces what it must not or leaves a partial file behind.

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace fieldlidar::io {

/// Whole file as bytes; throws fieldlidar::Error naming the file when it is missing or unreadable.
std::vector<std::byte> read_file_bytes(const std::filesystem::path& path);

/// Lower-case extension without the dot ("bin", "pcd", ...), "" when there is none.
std::string extension_of(const std::filesystem::path& path);

/// Throws fieldlidar::Error naming `path` when it may not be written as an output:
/// - its folder does not exist, or it is a folder;
/// - it exists and `overwrite` is false (nothing the user has is replaced without being asked);
/// - it exists and is not a regular file: a device node, FIFO, socket or symbolic link is never
///   replaced, even with `overwrite`;
/// - it is the same file (device and inode) as one of `inputs`.
void check_writable(const std::filesystem::path& path, bool overwrite,
                    const std::vector<std::filesystem::path>& inputs = {});

/// Writes `size` bytes to `path` through a temporary file in the same folder: every write is
/// checked, the data is flushed to the disk (fsync) and the file closed before it is renamed over
/// `path`. On any failure (disk full, file size limit, I/O error) the temporary file is removed,
/// `path` is left as it was, and fieldlidar::Error names the file and the cause. Runs
/// check_writable(path, overwrite) first and again just before the rename.
void write_file_atomic(const std::filesystem::path& path, const void* data, std::size_t size,
                       bool overwrite);
inline void write_file_atomic(const std::filesystem::path& path, std::string_view text,
                              bool overwrite) {
  write_file_atomic(path, text.data(), text.size(), overwrite);
}

/// Options shared by all writers.
struct WriteOptions {
  bool overwrite = false;   ///< replace an existing regular file
  bool binary = true;       ///< binary encoding where the format has a choice (PCD, PLY)
  bool compressed = false;  ///< PCD binary_compressed
  /// Per-point time as `time` offsets from the sweep start (s) even when the cloud has a stamp
  /// (by default a cloud with stamp_s != 0 gets absolute `timestamp`s, one with stamp_s == 0
  /// offsets): one schema for every file of a sequence whose first stamp may be 0.
  bool time_offsets = false;
};

}  // namespace fieldlidar::io
