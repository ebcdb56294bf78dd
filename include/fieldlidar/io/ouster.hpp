#pragma once
/// \file Ouster sensor metadata (JSON) and lidar/IMU packets (LEGACY and RNG19_RFL8_SIG16_NIR16
/// profiles), assembled into organized frames.

#include <cstddef>
#include <cstdint>
#include <deque>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "fieldlidar/core/point_cloud.hpp"
#include "fieldlidar/core/sensor_model.hpp"

namespace fieldlidar::io {

enum class OusterProfile { kLegacy, kRng19Rfl8Sig16Nir16 };
std::string to_string(OusterProfile profile);

/// What decoding needs from the sensor's metadata JSON. Both the older flat layout (all keys at
/// the top level, `data_format` optional) and the newer nested one (`sensor_info`,
/// `beam_intrinsics`, `lidar_intrinsics`, `lidar_data_format`, `config_params`) are read.
struct OusterMetadata {
  std::string prod_line;                           ///< e.g. "OS-1-64", empty when absent
  std::string prod_sn;                             ///< serial number, empty when absent
  std::string firmware;                            ///< build_rev, e.g. "v2.3.0"
  std::string lidar_mode;                          ///< e.g. "1024x10"
  std::optional<std::uint32_t> initialization_id;  ///< checked against RNG19 packet headers
  OusterProfile profile = OusterProfile::kLegacy;
  int columns_per_frame = 1024;
  int columns_per_packet = 16;
  int pixels_per_column = 64;
  int column_window_first = 0;  ///< first column the sensor sends (azimuth window)
  int column_window_last = 1023;
  double rotation_rate_hz = 10;
  std::vector<double> beam_altitude_deg;  ///< per beam (pixel row), beam 0 = top
  std::vector<double> beam_azimuth_deg;   ///< per beam, offset from the column's encoder angle
  double lidar_origin_to_beam_origin_mm = 0;
  Eigen::Matrix4d lidar_to_sensor_transform = Eigen::Matrix4d::Identity();  ///< mm translation
  std::uint16_t udp_port_lidar = 7502;
  std::uint16_t udp_port_imu = 7503;
};

/// Parses metadata JSON text; `source` names it in errors. Throws fieldlidar::Error naming the
/// missing or inconsistent field.
OusterMetadata parse_ouster_metadata(std::string_view json_text, const std::string& source);
OusterMetadata read_ouster_metadata(const std::filesystem::path& path);
/// The SensorModel of the metadata (rings sorted ascending, so ring 0 = the lowest beam).
SensorModel sensor_model_of(const OusterMetadata& meta);
/// Expected UDP payload size of one lidar packet for this metadata.
std::size_t ouster_lidar_packet_bytes(const OusterMetadata& meta);

/// One column of a decoded packet.
struct OusterColumn {
  std::uint64_t timestamp_ns = 0;
  std::uint16_t measurement_id = 0;  ///< column index in the frame
  std::uint16_t frame_id = 0;
  bool valid = false;  ///< the sensor marked the column as carrying data
};

/// Precomputed per-pixel geometry (ouster-sdk's xyz look-up table, written from the manual's
/// formulas): a point is `direction * range + offset` in the sensor frame (m).
class OusterDecoder {
 public:
  explicit OusterDecoder(OusterMetadata meta);
  const OusterMetadata& metadata() const { return meta_; }
  std::size_t packet_bytes() const { return packet_bytes_; }
  /// Ring (0 = lowest) of beam `b` (pixel row in the packet).
  std::uint16_t ring_of_beam(int b) const { return ring_of_beam_[std::size_t(b)]; }

  /// Decodes one lidar packet: fills `columns` (columns_per_packet entries) and `points`
  /// (columns_per_packet * pixels_per_column, column-major, beam order; no-return pixels are
  /// all-zero points). Throws fieldlidar::Error on a wrong size, a packet type other than lidar
  /// data, a column id out of range, or an initialization id that differs from the metadata.
  void decode(std::span<const std::uint8_t> bytes, std::vector<OusterColumn>& columns,
              std::vector<Point>& points) const;

 private:
  OusterMetadata meta_;
  std::size_t packet_bytes_ = 0;
  std::vector<Eigen::Vector3f> direction_;  ///< per (column, beam): column * h + beam
  std::vector<Eigen::Vector3f> offset_m_;
  std::vector<std::uint16_t> ring_of_beam_;
};

/// An IMU sample of an Ouster IMU packet (48 bytes): sensor clock, IMU frame.
struct OusterImuSample {
  double stamp_s = 0;
  Eigen::Vector3d gyro_rad_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel_m_s2 = Eigen::Vector3d::Zero();
};
/// Throws fieldlidar::Error when the packet is not 48 bytes.
OusterImuSample decode_ouster_imu_packet(std::span<const std::uint8_t> bytes);

/// One assembled frame: organized cloud, rows = rings (row 0 = lowest beam), columns in
/// measurement-id order; time = s after stamp_s (the frame's first column timestamp, sensor clock).
struct OusterFrame {
  PointCloud cloud;
  std::uint16_t frame_id = 0;
  std::size_t columns_received = 0;
  bool complete = false;  ///< every column of the column window arrived
};

/// Groups decoded packets into frames by frame id.
class OusterFrameAssembler {
 public:
  explicit OusterFrameAssembler(OusterMetadata meta) : decoder_(std::move(meta)) {}
  const OusterDecoder& decoder() const { return decoder_; }
  void add_packet(std::span<const std::uint8_t> bytes, const std::string& source);
  void finish();
  std::optional<OusterFrame> pop();

 private:
  void start_frame(std::uint16_t frame_id);
  void close_frame();

  OusterDecoder decoder_;
  std::vector<OusterColumn> columns_;
  std::vector<Point> points_;
  std::deque<OusterFrame> ready_;
  bool open_ = false;
  std::uint16_t frame_id_ = 0;
  std::vector<std::uint64_t> column_ts_;  ///< 0 = column not received
  std::vector<Point> frame_points_;       ///< ring-major organized buffer
  std::size_t packets_ = 0;
};

}  // namespace fieldlidar::io
