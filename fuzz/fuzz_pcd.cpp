// libFuzzer target: the PCD reader (header checks, ascii parser, PCL's binary/LZF body decoding)
// must return a cloud or throw fieldlidar::Error.
#include <cstddef>
#include <cstdint>
#include <span>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/pcd.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const auto cloud = fieldlidar::io::parse_pcd(
        std::span(reinterpret_cast<const std::byte*>(data), size), "fuzz");
    (void)cloud.valid_count();
  } catch (const fieldlidar::Error&) {
  }
  return 0;
}
