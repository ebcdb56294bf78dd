#include "fieldlidar/io/label_file.hpp"

#include <cstring>

#include "fieldlidar/core/error.hpp"

namespace fieldlidar::io {

std::vector<std::uint32_t> parse_labels(std::span<const std::byte> bytes,
                                        const std::string& source) {
  if (bytes.size() % sizeof(std::uint32_t) != 0)
    throw Error(source + ": .label size " + std::to_string(bytes.size()) +
                " bytes is not a multiple of 4 (uint32 per point); truncated or not a label file");
  std::vector<std::uint32_t> labels(bytes.size() / sizeof(std::uint32_t));
  if (!labels.empty()) std::memcpy(labels.data(), bytes.data(), bytes.size());
  return labels;
}

std::vector<std::uint32_t> read_labels(const std::filesystem::path& path) {
  const auto bytes = read_file_bytes(path);
  return parse_labels(bytes, path.string());
}

std::vector<std::uint32_t> read_labels(const std::filesystem::path& path, std::size_t point_count) {
  auto labels = read_labels(path);
  if (labels.size() != point_count)
    throw Error(path.string() + ": has " + std::to_string(labels.size()) +
                " labels for a scan of " + std::to_string(point_count) + " points");
  return labels;
}

void write_labels(const std::filesystem::path& path, std::span<const std::uint32_t> labels,
                  const WriteOptions& options) {
  write_file_atomic(path, labels.data(), labels.size_bytes(), options.overwrite);
}

}  // namespace fieldlidar::io
