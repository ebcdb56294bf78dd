// libFuzzer target: Ouster lidar and IMU packets. Byte 0 picks the layout (even: OS-1-64 LEGACY,
// odd: OS-2-128 RNG19_RFL8_SIG16_NIR16; bit 1: also parse the rest as metadata JSON); the rest is
// the packet, fed to the decoder and the frame assembler, which must succeed or throw
// fieldlidar::Error.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/ouster.hpp"

namespace {

fieldlidar::io::OusterMetadata layout(bool rng19) {
  fieldlidar::io::OusterMetadata m;
  const int beams = rng19 ? 128 : 64;
  m.profile = rng19 ? fieldlidar::io::OusterProfile::kRng19Rfl8Sig16Nir16
                    : fieldlidar::io::OusterProfile::kLegacy;
  m.pixels_per_column = beams;
  m.columns_per_frame = 512;
  m.column_window_last = 511;
  for (int b = 0; b < beams; ++b) {
    m.beam_altitude_deg.push_back(20.0 - 40.0 * b / (beams - 1));
    m.beam_azimuth_deg.push_back((b % 4 - 1.5) * 1.4);
  }
  m.lidar_origin_to_beam_origin_mm = 12.163;
  return m;
}

// Decoders and assemblers are built once, before the first (timed) unit: their look-up tables
// hold columns x beams entries. The assemblers are reused; finish() empties them.
struct Fixture {
  fieldlidar::io::OusterDecoder legacy{layout(false)};
  fieldlidar::io::OusterDecoder rng19{layout(true)};
  fieldlidar::io::OusterFrameAssembler legacy_frames{layout(false)};
  fieldlidar::io::OusterFrameAssembler rng19_frames{layout(true)};
};
Fixture* fixture = nullptr;

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  fixture = new Fixture();  // lives for the whole process
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const auto& legacy = fixture->legacy;
  const auto& rng19 = fixture->rng19;
  const bool use_rng19 = data[0] & 1;
  const std::span<const std::uint8_t> packet(data + 1, size - 1);
  std::vector<fieldlidar::io::OusterColumn> columns;
  std::vector<fieldlidar::Point> points;
  try {
    (use_rng19 ? rng19 : legacy).decode(packet, columns, points);
  } catch (const fieldlidar::Error&) {
  }
  try {
    (void)fieldlidar::io::decode_ouster_imu_packet(packet);
  } catch (const fieldlidar::Error&) {
  }
  auto& assembler = use_rng19 ? fixture->rng19_frames : fixture->legacy_frames;
  try {
    assembler.add_packet(packet, "fuzz");
  } catch (const fieldlidar::Error&) {
  }
  assembler.finish();
  while (auto f = assembler.pop()) (void)f->cloud.valid_count();
  if (data[0] & 2) {
    try {
      (void)fieldlidar::io::parse_ouster_metadata(
          std::string_view(reinterpret_cast<const char*>(packet.data()), packet.size()), "fuzz");
    } catch (const fieldlidar::Error&) {
    }
  }
  return 0;
}
