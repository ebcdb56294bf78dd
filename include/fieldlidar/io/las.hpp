#pragma once
/// \file ASPRS LAS 1.0-1.4 point clouds (read only), point data record formats 0-10, uncompressed.
///
/// LAS coordinates are int32 counts times a scale plus an offset, often in a projected frame
/// (UTM: x ~ 10^5 m, y ~ 10^6 m) where float32 keeps only ~0.5 m. The reader therefore returns
/// points relative to a local origin (see las_local_origin()): p_cloud = p_las - origin_m, with
/// the origin computed in double precision and reported beside the cloud.

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

#include <Eigen/Core>

#include "fieldlidar/core/point_cloud.hpp"

namespace fieldlidar::io {

/// The public header block of a LAS file (fields named as in the ASPRS specification).
struct LasHeader {
  std::uint8_t version_major = 1;
  std::uint8_t version_minor = 2;
  std::uint16_t global_encoding = 0;
  std::string system_identifier;
  std::string generating_software;
  std::uint16_t header_size = 0;           ///< bytes of the public header block
  std::uint32_t offset_to_point_data = 0;  ///< bytes from the file start to the first point
  std::uint32_t vlr_count = 0;             ///< variable length records
  std::uint8_t point_format = 0;  ///< point data record format, 0-10 (compression bits cleared)
  bool compressed = false;        ///< LAZ: bit 7 (or 6) of the format id was set
  std::uint16_t point_record_length = 0;  ///< bytes per point record (>= the format's size)
  std::uint64_t point_count = 0;          ///< number of point records (64-bit in LAS 1.4)
  std::array<std::uint64_t, 15> points_by_return{};
  Eigen::Vector3d scale{1, 1, 1};   ///< m per integer count
  Eigen::Vector3d offset{0, 0, 0};  ///< m
  Eigen::Vector3d min{0, 0, 0};     ///< m, as stored in the header
  Eigen::Vector3d max{0, 0, 0};     ///< m, as stored in the header

  bool has_gps_time() const;  ///< formats 1 and 3-10
};

/// Bytes of the fixed part of a point record of `format` (0-10); 0 for an unknown format.
std::size_t las_point_size(std::uint8_t format);

/// The local origin (m, in the LAS frame) that read_las() subtracts from every point: per axis,
/// 0 when the header bounds lie within +-1 km (float32 keeps < 0.1 mm there), else the header
/// minimum rounded down to a whole kilometre, so that |p_cloud| stays within a few km and float32
/// keeps better than 1 mm.
Eigen::Vector3d las_local_origin(const LasHeader& header);

/// Parses and checks the public header against the file size (`file_size` = total bytes).
/// Throws fieldlidar::Error naming `source` for a wrong magic, an unsupported version or format,
/// a compressed (LAZ) file, or counts, offsets and record lengths that do not fit in the file.
LasHeader parse_las_header(std::span<const std::byte> bytes, std::uint64_t file_size,
                           const std::string& source);
/// Reads only the header block of a LAS file (cheap even for large files).
LasHeader read_las_header(const std::filesystem::path& path);

/// A LAS file's points, in the local frame p_cloud = p_las - origin_m.
struct LasCloud {
  /// intensity, time (GPS time - stamp_s), labels (raw LAS class code); cloud.origin_m = origin_m
  PointCloud cloud;
  LasHeader header;
  Eigen::Vector3d origin_m{0, 0, 0};  ///< las_local_origin(header)
};

/// Parses a whole LAS file held in memory. Per point: intensity (uint16 as float), GPS time as an
/// offset from the earliest point (cloud.stamp_s = earliest GPS time, s), and the classification
/// as cloud.labels (raw LAS class code: 2 = ground, ...; formats 0-5 keep the low 5 bits).
LasCloud parse_las(std::span<const std::byte> bytes, const std::string& source);
LasCloud read_las(const std::filesystem::path& path);

}  // namespace fieldlidar::io
