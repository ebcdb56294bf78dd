#include "fieldlidar/io/velodyne.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <numeric>

#include "fieldlidar/core/error.hpp"

namespace fieldlidar::io {
namespace {

constexpr std::size_t kBlocks = 12;
constexpr std::size_t kBlockBytes = 100;
constexpr std::size_t kChannels = 32;
constexpr int kFullTurnCdeg = 36000;

/// Per-model decoding tables from the manufacturers' manuals.
struct ModelTable {
  int lasers = 0;
  std::array<double, 64> vertical_deg{};
  std::array<double, 64> azimuth_offset_deg{};
  std::array<double, 64> vertical_offset_m{};  ///< beam origin height above the sensor origin
  double distance_unit_m = 0.002;
  double block_period_us = 0;  ///< time between two firing sequences (block azimuths)
  // Per-channel firing time within the block, µs, and the laser a channel belongs to.
  std::array<double, kChannels> channel_time_us{};
  std::array<int, kChannels> channel_laser{};
  std::array<std::uint16_t, 64> ring{};
  std::array<float, 64> cos_vert{}, sin_vert{};
  std::array<int, 64> azimuth_offset_cdeg{};
};

void finish_table(ModelTable& t) {
  std::vector<int> order(t.lasers);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return t.vertical_deg[a] < t.vertical_deg[b]; });
  for (int r = 0; r < t.lasers; ++r) t.ring[order[r]] = std::uint16_t(r);
  for (int l = 0; l < t.lasers; ++l) {
    const double v = t.vertical_deg[l] * std::numbers::pi / 180.0;
    t.cos_vert[l] = float(std::cos(v));
    t.sin_vert[l] = float(std::sin(v));
    t.azimuth_offset_cdeg[l] = int(std::lround(t.azimuth_offset_deg[l] * 100.0));
  }
}

ModelTable make_vlp16() {
  // VLP-16 user manual: laser IDs 0..15 at -15, 1, -13, 3, ... deg; each block holds two firing
  // sequences of 16 lasers, 2.304 µs apart, a sequence every 55.296 µs; vertical correction in mm.
  ModelTable t;
  t.lasers = 16;
  const double vert[16] = {-15, 1, -13, 3, -11, 5, -9, 7, -7, 9, -5, 11, -3, 13, -1, 15};
  const double corr_mm[16] = {11.2, -0.7, 9.7, -2.2, 8.1, -3.7, 6.6, -5.1,
                              5.1,  -6.6, 3.7, -8.1, 2.2, -9.7, 0.7, -11.2};
  for (int l = 0; l < 16; ++l) {
    t.vertical_deg[l] = vert[l];
    t.vertical_offset_m[l] = corr_mm[l] * 1e-3;
  }
  t.block_period_us = 110.592;
  for (std::size_t c = 0; c < kChannels; ++c) {
    t.channel_laser[c] = int(c % 16);
    t.channel_time_us[c] = double(c / 16) * 55.296 + double(c % 16) * 2.304;
  }
  finish_table(t);
  return t;
}

ModelTable make_hdl32e() {
  // HDL-32E user manual: lasers interleaved -30.67, -9.33, -29.33, ... +10.67 deg; one laser every
  // 1.152 µs, a 32-laser sequence (with 8 idle slots) every 46.08 µs.
  ModelTable t;
  t.lasers = 32;
  const double vert[32] = {-30.67, -9.33, -29.33, -8.00, -28.00, -6.67, -26.67, -5.33,
                           -25.33, -4.00, -24.00, -2.67, -22.67, -1.33, -21.33, 0.00,
                           -20.00, 1.33,  -18.67, 2.67,  -17.33, 4.00,  -16.00, 5.33,
                           -14.67, 6.67,  -13.33, 8.00,  -12.00, 9.33,  -10.67, 10.67};
  for (int l = 0; l < 32; ++l) t.vertical_deg[l] = vert[l];
  t.block_period_us = 46.08;
  for (std::size_t c = 0; c < kChannels; ++c) {
    t.channel_laser[c] = int(c);
    t.channel_time_us[c] = double(c) * 1.152;
  }
  finish_table(t);
  return t;
}

ModelTable make_vlp32c() {
  // VLP-32C user manual: non-uniform elevations with per-laser azimuth offsets; lasers fire in
  // pairs every 2.304 µs, a full sequence every 55.296 µs; 4 mm distance granularity.
  ModelTable t;
  t.lasers = 32;
  const double vert[32] = {-25,    -1,    -1.667, -15.639, -11.31, 0,     -0.667, -8.843,
                           -7.254, 0.333, -0.333, -6.148,  -5.333, 1.333, 0.667,  -4,
                           -4.667, 1.667, 1,      -3.667,  -3.333, 3.333, 2.333,  -2.667,
                           -3,     7,     4.667,  -2.333,  -2,     15,    10.333, -1.333};
  const double az[32] = {1.4,  -4.2, 1.4,  -1.4, 1.4,  -1.4, 4.2,  -1.4, 1.4,  -4.2, 1.4,
                         -1.4, 4.2,  -1.4, 4.2,  -1.4, 1.4,  -4.2, 1.4,  -4.2, 4.2,  -1.4,
                         1.4,  -1.4, 1.4,  -1.4, 1.4,  -4.2, 4.2,  -1.4, 1.4,  -1.4};
  for (int l = 0; l < 32; ++l) {
    t.vertical_deg[l] = vert[l];
    t.azimuth_offset_deg[l] = az[l];
  }
  t.distance_unit_m = 0.004;
  t.block_period_us = 55.296;
  for (std::size_t c = 0; c < kChannels; ++c) {
    t.channel_laser[c] = int(c);
    t.channel_time_us[c] = double(c / 2) * 2.304;
  }
  finish_table(t);
  return t;
}

ModelTable make_hdl64e() {
  // HDL-64E S2/S3 nominal geometry (the SensorModel preset): upper block lasers 0..31 from +2 to
  // -8.33 deg, lower block lasers 32..63 from -8.83 to -24.33 deg. Units differ by a few tenths of
  // a degree from their factory calibration (db.xml), which this decoder does not read. Upper and
  // lower blocks fire together; one firing per 48 µs (2083 firings per turn at 10 Hz).
  ModelTable t;
  t.lasers = 64;
  for (int j = 0; j < 32; ++j) {
    t.vertical_deg[j] = 2.0 - j * (10.33 / 31.0);
    t.vertical_deg[32 + j] = -8.83 - j * 0.5;
  }
  t.block_period_us = 48.0;
  for (std::size_t c = 0; c < kChannels; ++c) {
    t.channel_laser[c] = int(c);
    t.channel_time_us[c] = 0.0;
  }
  finish_table(t);
  return t;
}

const ModelTable& table_of(VelodyneModel m) {
  static const ModelTable vlp16 = make_vlp16(), vlp32c = make_vlp32c(), hdl32e = make_hdl32e(),
                          hdl64e = make_hdl64e();
  switch (m) {
    case VelodyneModel::kVlp16:
      return vlp16;
    case VelodyneModel::kVlp32c:
      return vlp32c;
    case VelodyneModel::kHdl32e:
      return hdl32e;
    case VelodyneModel::kHdl64e:
      return hdl64e;
  }
  return vlp16;
}

/// cos/sin of every azimuth in 0.01 deg steps.
struct AzimuthTable {
  std::vector<float> cos_az, sin_az;
  AzimuthTable() : cos_az(kFullTurnCdeg), sin_az(kFullTurnCdeg) {
    for (int i = 0; i < kFullTurnCdeg; ++i) {
      const double a = i * std::numbers::pi / 18000.0;
      cos_az[i] = float(std::cos(a));
      sin_az[i] = float(std::sin(a));
    }
  }
};
const AzimuthTable& azimuth_table() {
  static const AzimuthTable t;
  return t;
}

std::uint16_t le16(const std::uint8_t* p) {
  return std::uint16_t(p[0] | (p[1] << 8));
}
std::uint32_t le32(const std::uint8_t* p) {
  return std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 |
         std::uint32_t(p[3]) << 24;
}

std::string hex_byte(unsigned v) {
  char buf[8];
  std::snprintf(buf, sizeof buf, "0x%02X", v & 0xFFu);
  return buf;
}

}  // namespace

std::string to_string(VelodyneModel model) {
  switch (model) {
    case VelodyneModel::kVlp16:
      return "VLP-16";
    case VelodyneModel::kVlp32c:
      return "VLP-32C";
    case VelodyneModel::kHdl32e:
      return "HDL-32E";
    case VelodyneModel::kHdl64e:
      return "HDL-64E";
  }
  return "unknown";
}

std::string to_string(VelodyneReturnMode mode) {
  switch (mode) {
    case VelodyneReturnMode::kStrongest:
      return "strongest";
    case VelodyneReturnMode::kLast:
      return "last";
    case VelodyneReturnMode::kDual:
      return "dual";
    case VelodyneReturnMode::kUnknown:
      return "unknown";
  }
  return "unknown";
}

SensorModel sensor_model_of(VelodyneModel model) {
  switch (model) {
    case VelodyneModel::kVlp16:
      return SensorModel::vlp16();
    case VelodyneModel::kVlp32c:
      return SensorModel::vlp32c();
    case VelodyneModel::kHdl32e:
      return SensorModel::hdl32e();
    case VelodyneModel::kHdl64e:
      return SensorModel::hdl64e();
  }
  return SensorModel::vlp16();
}

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
  VelodynePacketInfo info;
  info.timestamp_us = le32(p + 1200);
  const std::uint8_t mode_byte = p[1204], model_byte = p[1205];
  if (lower_blocks) {
    info.model = VelodyneModel::kHdl64e;  // bytes 1204/1205 are status type/value on the HDL-64E
    info.mode = VelodyneReturnMode::kUnknown;
  } else {
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
        throw Error("Velodyne data packet has unknown model (factory) byte " +
                    hex_byte(model_byte) +
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
  }
  const ModelTable& t = table_of(info.model);
  const AzimuthTable& az_table = azimuth_table();

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

void VelodyneSweepAssembler::add_packet(std::span<const std::uint8_t> bytes, double capture_stamp_s,
                                        const std::string& source) {
  const std::size_t packet = packets_++;
  scratch_.clear();
  VelodynePacketInfo info;
  try {
    info = decode_velodyne_packet(bytes, scratch_);
  } catch (const Error& e) {
    throw Error(source + ": data packet " + std::to_string(packet) + ": " + e.what());
  }
  if (model_ && *model_ != info.model)
    throw Error(source + ": data packet " + std::to_string(packet) + " is from a " +
                to_string(info.model) + " but the capture began with a " + to_string(*model_) +
                " (mixed sensors in one capture: split it by port or source address)");
  if (mode_ && *mode_ != info.mode)
    throw Error(source + ": data packet " + std::to_string(packet) + " switches return mode from " +
                to_string(*mode_) + " to " + to_string(info.mode));
  model_ = info.model;
  mode_ = info.mode;

  const std::int64_t ts = info.timestamp_us;
  if (last_timestamp_us_ >= 0 && ts + 1800'000'000LL < last_timestamp_us_) hour_offset_s_ += 3600;
  last_timestamp_us_ = ts;
  const double packet_sensor_s = hour_offset_s_ + double(ts) * 1e-6;

  for (const VelodyneReturn& r : scratch_) {
    const int az = r.firing_azimuth_cdeg;
    if (last_azimuth_cdeg_ >= 0) {
      if (az + kFullTurnCdeg / 2 < last_azimuth_cdeg_) {
        close_sweep(started_at_wrap_);
        started_at_wrap_ = true;
      } else if (az > last_azimuth_cdeg_ && az - last_azimuth_cdeg_ <= 500) {
        az_span_cdeg_ += az - last_azimuth_cdeg_;  // steps above 5 deg are gaps (lost packets)
      }
    }
    last_azimuth_cdeg_ = az;
    if (!started_) {
      started_ = true;
      start_sensor_s_ = packet_sensor_s + r.point.time;
      start_capture_s_ = capture_stamp_s + r.point.time;
    }
    if (!r.valid) continue;
    Point p = r.point;
    p.time = float(packet_sensor_s + double(r.point.time) - start_sensor_s_);
    points_.push_back(p);
  }
}

void VelodyneSweepAssembler::close_sweep(bool complete) {
  if (!started_) return;
  VelodyneSweep s;
  s.complete = complete;
  s.azimuth_span_deg = az_span_cdeg_ / 100.0;
  s.cloud.points = std::move(points_);
  s.cloud.stamp_s = start_capture_s_;
  s.cloud.fields.intensity = s.cloud.fields.ring = s.cloud.fields.time = true;
  s.cloud.width = std::uint32_t(s.cloud.points.size());
  s.cloud.height = 1;
  ready_.push_back(std::move(s));
  points_ = {};
  points_.reserve(ready_.back().cloud.size() + 1024);
  started_ = false;
  az_span_cdeg_ = 0;
}

void VelodyneSweepAssembler::finish() {
  close_sweep(false);
}

std::optional<VelodyneSweep> VelodyneSweepAssembler::pop() {
  if (ready_.empty()) return std::nullopt;
  VelodyneSweep s = std::move(ready_.front());
  ready_.pop_front();
  return s;
}

}  // namespace fieldlidar::io
