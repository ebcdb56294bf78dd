#pragma once
/// \file SemanticKITTI `.label` files: one little-endian uint32 per point, in the order of the
/// scan's points (low 16 bits class, high 16 bits instance id; see core/labels.hpp).

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "fieldlidar/io/file_util.hpp"

namespace fieldlidar::io {

/// Parses `.label` bytes; throws fieldlidar::Error naming `source` when the size is not a multiple
/// of 4 bytes.
std::vector<std::uint32_t> parse_labels(std::span<const std::byte> bytes,
                                        const std::string& source);
std::vector<std::uint32_t> read_labels(const std::filesystem::path& path);
/// Reads labels and checks that there is one per point of a cloud of `point_count` points.
std::vector<std::uint32_t> read_labels(const std::filesystem::path& path, std::size_t point_count);
void write_labels(const std::filesystem::path& path, std::span<const std::uint32_t> labels,
                  const WriteOptions& options = {});

}  // namespace fieldlidar::io
