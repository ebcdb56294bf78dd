#include "velodyne_tables.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

namespace fieldlidar::io::detail {
namespace {

constexpr std::size_t kChannels = kVelodyneChannels;

void finish_table(VelodyneModelTable& t) {
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

VelodyneModelTable make_vlp16() {
  // VLP-16 user manual: laser IDs 0..15 at -15, 1, -13, 3, ... deg; each block holds two firing
  // sequences of 16 lasers, 2.304 µs apart, a sequence every 55.296 µs; vertical correction in mm.
  VelodyneModelTable t;
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

VelodyneModelTable make_hdl32e() {
  // HDL-32E user manual: lasers interleaved -30.67, -9.33, -29.33, ... +10.67 deg; one laser every
  // 1.152 µs, a 32-laser sequence (with 8 idle slots) every 46.08 µs.
  VelodyneModelTable t;
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

VelodyneModelTable make_vlp32c() {
  // VLP-32C user manual: non-uniform elevations with per-laser azimuth offsets; lasers fire in
  // pairs every 2.304 µs, a full sequence every 55.296 µs; 4 mm distance granularity.
  VelodyneModelTable t;
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

VelodyneModelTable make_hdl64e() {
  // HDL-64E S2/S3 nominal geometry (the SensorModel preset): upper block lasers 0..31 from +2 to
  // -8.33 deg, lower block lasers 32..63 from -8.83 to -24.33 deg. Units differ by a few tenths of
  // a degree from their factory calibration (db.xml), which this decoder does not read. Upper and
  // lower blocks fire together; one firing per 48 µs (2083 firings per turn at 10 Hz).
  VelodyneModelTable t;
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

}  // namespace

const VelodyneModelTable& velodyne_model_table(VelodyneModel model) {
  static const VelodyneModelTable vlp16 = make_vlp16(), vlp32c = make_vlp32c(),
                                  hdl32e = make_hdl32e(), hdl64e = make_hdl64e();
  switch (model) {
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

VelodyneAzimuthTable::VelodyneAzimuthTable()
    : cos_az(kVelodyneFullTurnCdeg), sin_az(kVelodyneFullTurnCdeg) {
  for (int i = 0; i < kVelodyneFullTurnCdeg; ++i) {
    const double a = i * std::numbers::pi / 18000.0;
    cos_az[i] = float(std::cos(a));
    sin_az[i] = float(std::sin(a));
  }
}

const VelodyneAzimuthTable& velodyne_azimuth_table() {
  static const VelodyneAzimuthTable t;
  return t;
}

}  // namespace fieldlidar::io::detail
