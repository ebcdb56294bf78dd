// libFuzzer target: the LAS reader must return points or throw fieldlidar::Error, whatever the
// header's counts, offsets and record lengths say.
#include <cstddef>
#include <cstdint>
#include <span>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/las.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span bytes(reinterpret_cast<const std::byte*>(data), size);
  try {
    const auto las = fieldlidar::io::parse_las(bytes, "fuzz");
    (void)las.cloud.valid_count();
  } catch (const fieldlidar::Error&) {
  }
  try {
    (void)fieldlidar::io::parse_las_header(bytes, size, "fuzz");
  } catch (const fieldlidar::Error&) {
  }
  return 0;
}
