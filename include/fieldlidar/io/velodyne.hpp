#pragma once
/// \file Velodyne data packets (VLP-16, VLP-32C, HDL-32E, HDL-64E; single and dual return) and
/// their assembly into full sweeps.

#include <cstddef>
#include <cstdint>
#include <deque>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "fieldlidar/core/point_cloud.hpp"
#include "fieldlidar/core/sensor_model.hpp"

namespace fieldlidar::io {

enum class VelodyneModel { kVlp16, kVlp32c, kHdl32e, kHdl64e };
enum class VelodyneReturnMode { kStrongest, kLast, kDual, kUnknown };

std::string to_string(VelodyneModel model);
std::string to_string(VelodyneReturnMode mode);
/// The SensorModel preset matching a Velodyne model (beam table, resolution, range limits).
SensorModel sensor_model_of(VelodyneModel model);

/// UDP payload size of a Velodyne data packet: 12 blocks of 100 bytes, 4-byte timestamp, 2 bytes.
inline constexpr std::size_t kVelodyneDataPacketBytes = 1206;
/// UDP payload size of a Velodyne position (GPS) packet, which carries no points.
inline constexpr std::size_t kVelodynePositionPacketBytes = 512;

/// One return of a decoded packet. `point.time` is the firing time in s after the packet's
/// timestamp; `point.ring` follows SensorModel (0 = lowest beam).
struct VelodyneReturn {
  Point point;
  std::uint16_t firing_azimuth_cdeg =
      0;               ///< 0.01 deg, azimuth of the firing sequence (no laser offset)
  bool valid = false;  ///< false for "no return" (distance 0)
};

struct VelodynePacketInfo {
  VelodyneModel model = VelodyneModel::kVlp16;
  VelodyneReturnMode mode = VelodyneReturnMode::kStrongest;
  std::uint32_t timestamp_us = 0;  ///< µs past the top of the hour, first firing of the packet
};

/// Decodes one data packet (1206 bytes). Appends every firing (valid or not) to `out` in firing
/// order. The model comes from the factory byte (0x21 HDL-32E, 0x22 VLP-16, 0x28 VLP-32C) or, for
/// the HDL-64E which has none, from its 0xDDFF lower-block flags. Throws fieldlidar::Error on a
/// wrong size, bad block flag, an unknown model byte or an azimuth >= 360 deg.
VelodynePacketInfo decode_velodyne_packet(std::span<const std::uint8_t> bytes,
                                          std::vector<VelodyneReturn>& out);

/// One assembled sweep.
struct VelodyneSweep {
  PointCloud cloud;       ///< valid returns; time = s after cloud.stamp_s, ring set
  bool complete = false;  ///< began and ended at the azimuth wrap (not a capture's first/last part)
  double azimuth_span_deg = 0;  ///< azimuth covered by the firings of this sweep
};

/// Cuts the stream of firings into sweeps where the azimuth wraps from ~360 to ~0 deg. Every
/// packet must come from the same model and return mode (else fieldlidar::Error).
class VelodyneSweepAssembler {
 public:
  /// Feeds one data packet captured at `capture_stamp_s` (s since epoch); completed sweeps are
  /// queued for pop(). `source` names the input in error messages.
  void add_packet(std::span<const std::uint8_t> bytes, double capture_stamp_s,
                  const std::string& source);
  /// Ends the stream: the sweep in progress (if any points) is queued as incomplete.
  void finish();
  std::optional<VelodyneSweep> pop();
  std::optional<VelodyneModel> model() const { return model_; }
  std::optional<VelodyneReturnMode> mode() const { return mode_; }

 private:
  void close_sweep(bool complete);

  std::optional<VelodyneModel> model_;
  std::optional<VelodyneReturnMode> mode_;
  std::vector<VelodyneReturn> scratch_;
  std::deque<VelodyneSweep> ready_;
  // Sweep in progress.
  std::vector<Point> points_;
  double start_sensor_s_ = 0, start_capture_s_ = 0;
  bool started_ = false, started_at_wrap_ = false;
  int last_azimuth_cdeg_ = -1;
  double az_span_cdeg_ = 0;
  // Sensor clock unwrapping (the timestamp restarts every hour).
  double hour_offset_s_ = 0;
  std::int64_t last_timestamp_us_ = -1;
  std::size_t packets_ = 0;
};

}  // namespace fieldlidar::io
