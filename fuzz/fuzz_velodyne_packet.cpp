// libFuzzer target: Velodyne data packets. The input is cut into 1206-byte packets (the last one
// may be short) that go through the packet decoder and the sweep assembler; both must either
// succeed or throw fieldlidar::Error.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/velodyne.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::uint8_t> bytes(data, size);
  std::vector<fieldlidar::io::VelodyneReturn> out;
  try {
    (void)fieldlidar::io::decode_velodyne_packet(bytes, out);
  } catch (const fieldlidar::Error&) {
  }
  fieldlidar::io::VelodyneSweepAssembler assembler;
  try {
    for (std::size_t off = 0; off < size; off += fieldlidar::io::kVelodyneDataPacketBytes) {
      const auto n = std::min(fieldlidar::io::kVelodyneDataPacketBytes, size - off);
      assembler.add_packet(bytes.subspan(off, n), 1e9 + double(off) * 1e-6, "fuzz");
    }
    assembler.finish();
    while (auto s = assembler.pop()) (void)s->cloud.valid_count();
  } catch (const fieldlidar::Error&) {
  }
  return 0;
}
