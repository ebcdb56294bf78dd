#include "fieldlidar/io/las.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <vector>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/file_util.hpp"

namespace fieldlidar::io {

namespace {

// Byte offsets of the public header block (ASPRS LAS 1.4 R15, table 3; 1.0-1.3 share the first
// 227 bytes, 1.3 adds the waveform offset, 1.4 the extended counts).
constexpr std::size_t kHeaderSize12 = 227;
constexpr std::size_t kHeaderSize13 = 235;
constexpr std::size_t kHeaderSize14 = 375;

const char* kLazMessage = "compressed LAZ is not supported, decompress it first";

template <typename T>
T get(std::span<const std::byte> b, std::size_t at) {
  T v;
  std::memcpy(&v, b.data() + at, sizeof(T));
  return v;
}

std::string get_string(std::span<const std::byte> b, std::size_t at, std::size_t n) {
  std::string s(reinterpret_cast<const char*>(b.data() + at), n);
  s.erase(std::find(s.begin(), s.end(), '\0'), s.end());
  return s;
}

[[noreturn]] void las_fail(const std::string& source, const std::string& what) {
  throw Error(source + ": LAS " + what);
}

}  // namespace

bool LasHeader::has_gps_time() const {
  return point_format == 1 || point_format >= 3;
}

std::size_t las_point_size(std::uint8_t format) {
  // Table of point data record sizes, formats 0-10 (LAS 1.4 R15, section 2.6).
  static constexpr std::size_t kSizes[] = {20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67};
  return format <= 10 ? kSizes[format] : 0;
}

Eigen::Vector3d las_local_origin(const LasHeader& header) {
  constexpr double kKeepWithin_m = 1000.0;
  constexpr double kRound_m = 1000.0;
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  for (int a = 0; a < 3; ++a) {
    const double lo = header.min[a];
    const double hi = header.max[a];
    if (!std::isfinite(lo) || !std::isfinite(hi)) continue;
    if (std::max(std::abs(lo), std::abs(hi)) <= kKeepWithin_m) continue;
    origin[a] = std::floor(lo / kRound_m) * kRound_m;
  }
  return origin;
}

LasHeader parse_las_header(std::span<const std::byte> b, std::uint64_t file_size,
                           const std::string& source) {
  if (b.size() < 4 || std::memcmp(b.data(), "LASF", 4) != 0)
    las_fail(source, "file signature is not 'LASF' (not a LAS file)");
  if (b.size() < kHeaderSize12)
    las_fail(source, "header truncated: " + std::to_string(b.size()) + " bytes, need at least " +
                         std::to_string(kHeaderSize12));
  LasHeader h;
  const auto format_id = get<std::uint8_t>(b, 104);
  // LAZ files set bit 7 of the point format id (some older writers bit 6) on a format 0-10; any
  // other id above 10 is no format at all.
  h.compressed =
      (format_id & 0x80u) != 0 || ((format_id & 0x40u) != 0 && (format_id & 0x3Fu) <= 10);
  if (h.compressed) las_fail(source, kLazMessage);
  if (format_id > 10)
    las_fail(source, "point data format " + std::to_string(format_id) +
                         " is invalid (LAS defines 0-10; compressed LAZ sets bit 7, 128 and up)");
  h.global_encoding = get<std::uint16_t>(b, 6);
  h.version_major = get<std::uint8_t>(b, 24);
  h.version_minor = get<std::uint8_t>(b, 25);
  if (h.version_major != 1 || h.version_minor > 4)
    las_fail(source, "version " + std::to_string(h.version_major) + "." +
                         std::to_string(h.version_minor) + " is not supported (1.0-1.4)");
  h.system_identifier = get_string(b, 26, 32);
  h.generating_software = get_string(b, 58, 32);
  h.header_size = get<std::uint16_t>(b, 94);
  h.offset_to_point_data = get<std::uint32_t>(b, 96);
  h.vlr_count = get<std::uint32_t>(b, 100);
  h.point_format = format_id & 0x3Fu;
  h.point_record_length = get<std::uint16_t>(b, 105);
  const std::size_t need = h.version_minor >= 4   ? kHeaderSize14
                           : h.version_minor == 3 ? kHeaderSize13
                                                  : kHeaderSize12;
  if (h.header_size < need)
    las_fail(source, "header size field " + std::to_string(h.header_size) + " is below the " +
                         std::to_string(need) + " bytes of version 1." +
                         std::to_string(h.version_minor));
  if (b.size() < need || h.header_size > file_size)
    las_fail(source, "header truncated: file has " + std::to_string(file_size) + " bytes, header " +
                         std::to_string(h.header_size));
  if (h.point_format > 10)
    las_fail(source, "point data record format " + std::to_string(h.point_format) +
                         " is not supported (0-10)");
  const std::size_t min_record = las_point_size(h.point_format);
  if (h.point_record_length < min_record)
    las_fail(source, "point record length " + std::to_string(h.point_record_length) +
                         " is shorter than the " + std::to_string(min_record) +
                         " bytes of point format " + std::to_string(h.point_format));
  if (h.offset_to_point_data < h.header_size || h.offset_to_point_data > file_size)
    las_fail(source, "offset to point data " + std::to_string(h.offset_to_point_data) +
                         " is outside the file (header " + std::to_string(h.header_size) +
                         " bytes, file " + std::to_string(file_size) + " bytes)");

  h.point_count = get<std::uint32_t>(b, 107);
  for (int r = 0; r < 5; ++r) h.points_by_return[r] = get<std::uint32_t>(b, 111 + 4 * r);
  if (h.version_minor >= 4) {
    // LAS 1.4: the 64-bit counts are authoritative; the legacy ones may be 0 for formats 6-10.
    const auto count64 = get<std::uint64_t>(b, 247);
    if (count64 != 0) h.point_count = count64;
    for (int r = 0; r < 15; ++r) {
      const auto n = get<std::uint64_t>(b, 255 + 8 * r);
      if (n != 0 || r >= 5) h.points_by_return[r] = n;
    }
  }
  for (int a = 0; a < 3; ++a) {
    h.scale[a] = get<double>(b, 131 + 8 * a);
    h.offset[a] = get<double>(b, 155 + 8 * a);
    h.max[a] = get<double>(b, 179 + 16 * a);
    h.min[a] = get<double>(b, 187 + 16 * a);
  }
  static const char* kAxis[] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(h.scale[a]) || h.scale[a] == 0.0)
      las_fail(source, std::string(kAxis[a]) + " scale factor " + std::to_string(h.scale[a]) +
                           " is zero or not finite");
    if (!std::isfinite(h.offset[a]))
      las_fail(source, std::string(kAxis[a]) + " offset is not finite");
  }
  const std::uint64_t available = file_size - h.offset_to_point_data;
  if (h.point_count > available / h.point_record_length)
    las_fail(source, "truncated: header says " + std::to_string(h.point_count) + " points of " +
                         std::to_string(h.point_record_length) + " bytes but only " +
                         std::to_string(available) + " bytes follow the header");
  return h;
}

LasHeader read_las_header(const std::filesystem::path& path) {
  if (extension_of(path) == "laz") las_fail(path.string(), kLazMessage);
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw Error(path.string() + ": no such file");
  const auto file_size = std::filesystem::file_size(path, ec);
  if (ec) throw Error(path.string() + ": cannot determine its size");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path.string() + ": cannot open for reading");
  std::vector<std::byte> bytes(std::min<std::uint64_t>(file_size, kHeaderSize14));
  in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (!in) throw Error(path.string() + ": read failed");
  return parse_las_header(bytes, file_size, path.string());
}

LasCloud parse_las(std::span<const std::byte> bytes, const std::string& source) {
  LasCloud out;
  out.header = parse_las_header(bytes, bytes.size(), source);
  const LasHeader& h = out.header;
  out.origin_m = las_local_origin(h);

  const std::size_t n = static_cast<std::size_t>(h.point_count);
  const std::size_t stride = h.point_record_length;
  const bool extended = h.point_format >= 6;
  const std::size_t class_at = extended ? 16 : 15;
  const std::uint8_t class_mask = extended ? 0xFF : 0x1F;  // formats 0-5: bits 5-7 are flags
  const std::size_t gps_at = extended ? 22 : 20;
  const bool has_time = h.has_gps_time();
  // Coordinates: p = raw * scale + offset - origin, in double, so a projected frame keeps its mm.
  const Eigen::Vector3d shift = h.offset - out.origin_m;

  PointCloud& cloud = out.cloud;
  cloud.origin_m = out.origin_m;
  cloud.points.resize(n);
  cloud.labels.resize(n);
  cloud.width = static_cast<std::uint32_t>(std::min<std::size_t>(n, UINT32_MAX));
  cloud.height = 1;
  cloud.fields.intensity = true;
  cloud.fields.label = true;
  cloud.fields.time = has_time;
  std::vector<double> gps;
  if (has_time) gps.resize(n);
  double gps_min = std::numeric_limits<double>::infinity();

  const std::byte* rec = bytes.data() + h.offset_to_point_data;
  for (std::size_t i = 0; i < n; ++i, rec += stride) {
    std::int32_t xyz[3];
    std::uint16_t intensity;
    std::memcpy(xyz, rec, sizeof(xyz));
    std::memcpy(&intensity, rec + 12, sizeof(intensity));
    Point& p = cloud.points[i];
    p.x = static_cast<float>(xyz[0] * h.scale.x() + shift.x());
    p.y = static_cast<float>(xyz[1] * h.scale.y() + shift.y());
    p.z = static_cast<float>(xyz[2] * h.scale.z() + shift.z());
    p.intensity = intensity;
    cloud.labels[i] = static_cast<std::uint8_t>(rec[class_at]) & class_mask;
    if (has_time) {
      double t;
      std::memcpy(&t, rec + gps_at, sizeof(t));
      if (!std::isfinite(t))
        las_fail(source, "point " + std::to_string(i) + " has a NaN or infinite GPS time");
      gps[i] = t;
      gps_min = std::min(gps_min, t);
    }
  }
  if (has_time && n > 0) {
    cloud.stamp_s = gps_min;
    for (std::size_t i = 0; i < n; ++i) cloud.points[i].time = static_cast<float>(gps[i] - gps_min);
  }
  return out;
}

LasCloud read_las(const std::filesystem::path& path) {
  if (extension_of(path) == "laz") las_fail(path.string(), kLazMessage);
  const auto bytes = read_file_bytes(path);
  return parse_las(bytes, path.string());
}

}  // namespace fieldlidar::io
