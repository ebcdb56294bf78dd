// decode_velodyne_packet: one 1206-byte data packet into its firings.
#include <array>
#include <cmath>
#include <cstdio>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/velodyne.hpp"
#include "little_endian.hpp"
#include "velodyne_tables.hpp"

namespace fieldlidar::io {
namespace {

using detail::le16;
using detail::le32;
constexpr std::size_t kBlocks = detail::kVelodyneBlocks;
constexpr std::size_t kBlockBytes = detail::kVelodyneBlockBytes;
constexpr std::size_t kChannels = detail::kVelodyneChannels;
constexpr int kFullTurnCdeg = detail::kVelodyneFullTurnCdeg;

std::string hex_byte(unsigned v) {
  char buf[8];
  std::snprintf(buf, sizeof buf, "0x%02X", v & 0xFFu);
  return buf;
}

/// Model, return mode and timestamp from the packet's last 6 bytes. The HDL-64E (`lower_blocks`:
/// some block carries the 0xDDFF flag) has no model byte, and its bytes 1204/1205 are status.
VelodynePacketInfo packet_info(const std::uint8_t* p, bool lower_blocks) {
  VelodynePacketInfo info;
  info.timestamp_us = le32(p + 1200);
  const std::uint8_t mode_byte = p[1204], model_byte = p[1205];
  if (lower_blocks) {
    info.model = VelodyneModel::kHdl64e;  // bytes 1204/1205 are status type/value on the HDL-64E
    info.mode = VelodyneReturnMode::kUnknown;
    return info;
  }
  switch (model_byte) {
    case 0x21:
      info.model = VelodyneModel::kHdl32e;
      break;
    case 0x22:
      info.model = VelodyneModel::kVlp16;
      break;
    case 0x28:
      info.model = VelodyneModel::kVlp32c;
      break;
    default:
      throw Error("Velodyne data packet has unknown model (factory) byte " + hex_byte(model_byte) +
                  " (known: 0x21 HDL-32E, 0x22 VLP-16, 0x28 VLP-32C; HDL-64E packets carry "
                  "0xDDFF lower-block flags)");
  }
  switch (mode_byte) {
    case 0x37:
      info.mode = VelodyneReturnMode::kStrongest;
      break;
    case 0x38:
      info.mode = VelodyneReturnMode::kLast;
      break;
    case 0x39:
      info.mode = VelodyneReturnMode::kDual;
      break;
    default:
      throw Error("Velodyne data packet has unknown return-mode byte " + hex_byte(mode_byte) +
                  " (known: 0x37 strongest, 0x38 last, 0x39 dual)");
  }
  return info;
}

}  // namespace

VelodynePacketInfo decode_velodyne_packet(std::span<const std::uint8_t> bytes,
                                          std::vector<VelodyneReturn>& out) {
  if (bytes.size() != kVelodyneDataPacketBytes)
    throw Error("Velodyne data packet has " + std::to_string(bytes.size()) + " bytes, expected " +
                std::to_string(kVelodyneDataPacketBytes));
  const std::uint8_t* p = bytes.data();
  bool lower_blocks = false;
  std::array<int, kBlocks> azimuth{};
  for (std::size_t b = 0; b < kBlocks; ++b) {
    const std::uint8_t* blk = p + b * kBlockBytes;
    const std::uint16_t flag = le16(blk);
    if (flag == 0xDDFF)
      lower_blocks = true;
    else if (flag != 0xEEFF)
      throw Error("Velodyne data packet block " + std::to_string(b) + " has flag " +
                  hex_byte(flag >> 8) + hex_byte(flag).substr(2) + ", expected 0xEEFF or 0xDDFF");
    azimuth[b] = le16(blk + 2);
    if (azimuth[b] >= kFullTurnCdeg)
      throw Error("Velodyne data packet block " + std::to_string(b) + " has azimuth " +
                  std::to_string(azimuth[b]) + " (0.01 deg), expected < 36000");
  }
  const VelodynePacketInfo info = packet_info(p, lower_blocks);
  const detail::VelodyneModelTable& t = detail::velodyne_model_table(info.model);
  const detail::VelodyneAzimuthTable& az_table = detail::velodyne_azimuth_table();

  // Blocks sharing an azimuth (the two returns of dual mode, the upper/lower halves of the
  // HDL-64E) belong to one firing sequence; sequences follow each other every block_period_us.
  std::array<int, kBlocks> firing{};
  std::array<int, kBlocks> firing_azimuth{};
  int n_firings = 0;
  for (std::size_t b = 0; b < kBlocks; ++b) {
    if (b == 0 || azimuth[b] != azimuth[b - 1]) firing_azimuth[n_firings++] = azimuth[b];
    firing[b] = n_firings - 1;
  }
  auto gap_after = [&](int f) {
    int g = 0;
    if (f + 1 < n_firings)
      g = firing_azimuth[f + 1] - firing_azimuth[f];
    else if (f > 0)
      g = firing_azimuth[f] - firing_azimuth[f - 1];
    if (g < 0) g += kFullTurnCdeg;
    return g > 1000 ? 0 : g;  // a step above 10 deg is not one firing period: do not interpolate
  };

  out.reserve(out.size() + kBlocks * kChannels);
  for (std::size_t b = 0; b < kBlocks; ++b) {
    const std::uint8_t* blk = p + b * kBlockBytes;
    const int f = firing[b];
    const int gap = gap_after(f);
    const int laser_base = (le16(blk) == 0xDDFF) ? 32 : 0;
    for (std::size_t c = 0; c < kChannels; ++c) {
      const std::uint8_t* ch = blk + 4 + c * 3;
      const int laser = t.channel_laser[c] + laser_base;
      const double t_in_block_us = t.channel_time_us[c];
      int az = firing_azimuth[f] + int(std::lround(gap * t_in_block_us / t.block_period_us)) +
               t.azimuth_offset_cdeg[laser];
      az %= kFullTurnCdeg;
      if (az < 0) az += kFullTurnCdeg;
      const std::uint16_t raw = le16(ch);
      VelodyneReturn r;
      r.firing_azimuth_cdeg = std::uint16_t(firing_azimuth[f]);
      r.valid = raw != 0;
      const float d = float(raw * t.distance_unit_m);
      const float xy = d * t.cos_vert[laser];
      // Velodyne azimuth grows clockwise seen from above; x forward, y left, z up.
      r.point.x = xy * az_table.cos_az[az];
      r.point.y = -xy * az_table.sin_az[az];
      r.point.z = d * t.sin_vert[laser] + float(t.vertical_offset_m[laser]);
      r.point.intensity = float(ch[2]);
      r.point.ring = t.ring[laser];
      r.point.time = float((f * t.block_period_us + t_in_block_us) * 1e-6);
      out.push_back(r);
    }
  }
  return info;
}

}  // namespace fieldlidar::io
