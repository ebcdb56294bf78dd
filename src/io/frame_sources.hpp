#pragma once
// Factories of the FrameSource implementations (private to the io module).

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "fieldlidar/io/frame_source.hpp"

namespace fieldlidar::io::detail {

/// One frame per file; `times` (empty, or one stamp per file) replaces the files' own stamps,
/// `warnings` are the source's from the start.
std::unique_ptr<FrameSource> open_cloud_files(std::vector<std::filesystem::path> files,
                                              const std::string& description,
                                              std::vector<double> times = {},
                                              std::vector<std::string> warnings = {});
/// Velodyne or Ouster, decided from the packets and the metadata option / sidecar JSON.
std::unique_ptr<FrameSource> open_pcap(const std::filesystem::path& capture,
                                       const SourceOptions& options);

}  // namespace fieldlidar::io::detail
