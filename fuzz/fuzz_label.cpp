// libFuzzer target: the SemanticKITTI .label reader must return labels or throw fieldlidar::Error.
#include <cstddef>
#include <cstdint>
#include <span>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/label_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const auto labels = fieldlidar::io::parse_labels(
        std::span(reinterpret_cast<const std::byte*>(data), size), "fuzz");
    if (labels.size() != size / 4) __builtin_trap();
  } catch (const fieldlidar::Error&) {
  }
  return 0;
}
