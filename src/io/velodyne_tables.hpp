#pragma once
// Decoding tables of the Velodyne models (beam geometry and firing timing from the manufacturers'
// manuals) and of the packets' azimuths.

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "fieldlidar/io/velodyne.hpp"

namespace fieldlidar::io::detail {

inline constexpr std::size_t kVelodyneBlocks = 12;       ///< blocks per data packet
inline constexpr std::size_t kVelodyneBlockBytes = 100;  ///< flag, azimuth, 32 channels
inline constexpr std::size_t kVelodyneChannels = 32;     ///< channels per block
inline constexpr int kVelodyneFullTurnCdeg = 36000;      ///< azimuths are in 0.01 deg

/// Per-model decoding tables from the manufacturers' manuals.
struct VelodyneModelTable {
  int lasers = 0;
  std::array<double, 64> vertical_deg{};
  std::array<double, 64> azimuth_offset_deg{};
  std::array<double, 64> vertical_offset_m{};  ///< beam origin height above the sensor origin
  double distance_unit_m = 0.002;
  double block_period_us = 0;  ///< time between two firing sequences (block azimuths)
  // Per-channel firing time within the block, µs, and the laser a channel belongs to.
  std::array<double, kVelodyneChannels> channel_time_us{};
  std::array<int, kVelodyneChannels> channel_laser{};
  std::array<std::uint16_t, 64> ring{};
  std::array<float, 64> cos_vert{}, sin_vert{};
  std::array<int, 64> azimuth_offset_cdeg{};
};

/// The table of `model`, built once.
const VelodyneModelTable& velodyne_model_table(VelodyneModel model);

/// cos/sin of every azimuth in 0.01 deg steps.
struct VelodyneAzimuthTable {
  std::vector<float> cos_az, sin_az;
  VelodyneAzimuthTable();
};

/// The azimuth table, built once.
const VelodyneAzimuthTable& velodyne_azimuth_table();

}  // namespace fieldlidar::io::detail
