// libFuzzer target: the KITTI pose, KITTI times and TUM text parsers must return a trajectory
// or throw fieldlidar::Error.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/trajectory_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  namespace io = fieldlidar::io;
  try {
    (void)io::parse_kitti_poses(text, "fuzz");
  } catch (const fieldlidar::Error&) {
  }
  try {
    const auto times = io::parse_kitti_times(text, "fuzz");
    (void)io::parse_kitti_poses(text, "fuzz", times);
  } catch (const fieldlidar::Error&) {
  }
  try {
    (void)io::parse_tum(text, "fuzz");
  } catch (const fieldlidar::Error&) {
  }
  return 0;
}
