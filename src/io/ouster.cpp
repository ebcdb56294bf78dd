// Ouster lidar and IMU packets -> points; frames assembled by frame id.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <numeric>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/ouster.hpp"

namespace fieldlidar::io {
namespace {

std::uint16_t le16(const std::uint8_t* p) {
  return std::uint16_t(p[0] | (p[1] << 8));
}
std::uint32_t le32(const std::uint8_t* p) {
  return std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 |
         std::uint32_t(p[3]) << 24;
}
std::uint64_t le64(const std::uint8_t* p) {
  return std::uint64_t(le32(p)) | std::uint64_t(le32(p + 4)) << 32;
}
float lef32(const std::uint8_t* p) {
  const std::uint32_t u = le32(p);
  float f;
  std::memcpy(&f, &u, 4);
  return f;
}

// Packet layouts (Ouster firmware user manual, "Lidar data format").
constexpr std::size_t kLegacyColumnHeader = 16;  // timestamp u64, measurement id, frame id, encoder
constexpr std::size_t kLegacyColumnFooter = 4;   // status u32, 0xFFFFFFFF when valid
constexpr std::size_t kRngPacketHeader = 32;     // type, frame id, init id, serial, ...
constexpr std::size_t kRngColumnHeader = 12;     // timestamp u64, measurement id, status
constexpr std::size_t kRngPacketFooter = 32;
constexpr std::size_t kChannelBytes = 12;
constexpr std::size_t kImuPacketBytes = 48;

}  // namespace

std::size_t ouster_lidar_packet_bytes(const OusterMetadata& m) {
  const std::size_t h = std::size_t(m.pixels_per_column);
  const std::size_t cols = std::size_t(m.columns_per_packet);
  if (m.profile == OusterProfile::kLegacy)
    return cols * (kLegacyColumnHeader + h * kChannelBytes + kLegacyColumnFooter);
  return kRngPacketHeader + cols * (kRngColumnHeader + h * kChannelBytes) + kRngPacketFooter;
}

OusterDecoder::OusterDecoder(OusterMetadata meta) : meta_(std::move(meta)) {
  packet_bytes_ = ouster_lidar_packet_bytes(meta_);
  const int w = meta_.columns_per_frame, h = meta_.pixels_per_column;
  direction_.resize(std::size_t(w) * std::size_t(h));
  offset_m_.resize(direction_.size());
  // Plain scalar loops with the trigonometry hoisted out of the inner loop: the tables hold
  // columns x beams entries (up to 2048 x 128), and unoptimised (Debug, sanitizer, fuzzing) builds
  // would otherwise spend seconds on per-entry Eigen expressions.
  double R[3][3], t_mm[3];
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) R[r][c] = meta_.lidar_to_sensor_transform(r, c);
    t_mm[r] = meta_.lidar_to_sensor_transform(r, 3);
  }
  const double n_mm = meta_.lidar_origin_to_beam_origin_mm;
  constexpr double kDeg = std::numbers::pi / 180.0;
  const std::size_t beams = std::size_t(h);
  std::vector<double> cos_az(beams), sin_az(beams), cos_alt(beams), sin_alt(beams);
  for (int b = 0; b < h; ++b) {
    const double az = -meta_.beam_azimuth_deg[std::size_t(b)] * kDeg;
    const double alt = meta_.beam_altitude_deg[std::size_t(b)] * kDeg;
    cos_az[std::size_t(b)] = std::cos(az);
    sin_az[std::size_t(b)] = std::sin(az);
    cos_alt[std::size_t(b)] = std::cos(alt);
    sin_alt[std::size_t(b)] = std::sin(alt);
  }
  for (int c = 0; c < w; ++c) {
    // Encoder angle of column c: the sensor spins clockwise seen from above, so the angle
    // decreases as the column index grows.
    const double enc = 2.0 * std::numbers::pi * (1.0 - double(c) / w);
    const double ce = std::cos(enc), se = std::sin(enc);
    for (int b = 0; b < h; ++b) {
      const std::size_t k = std::size_t(b);
      // cos(enc + az), sin(enc + az) by the angle-sum identities.
      const double cea = ce * cos_az[k] - se * sin_az[k];
      const double sea = se * cos_az[k] + ce * sin_az[k];
      const double dir[3] = {cea * cos_alt[k], sea * cos_alt[k], sin_alt[k]};
      // The beam leaves from a point n_mm off the rotation axis at the encoder angle.
      const double off_mm[3] = {n_mm * ce - n_mm * dir[0], n_mm * se - n_mm * dir[1],
                                -n_mm * dir[2]};
      const std::size_t i = std::size_t(c) * std::size_t(h) + k;
      for (int r = 0; r < 3; ++r) {
        const double d = R[r][0] * dir[0] + R[r][1] * dir[1] + R[r][2] * dir[2];
        const double o = R[r][0] * off_mm[0] + R[r][1] * off_mm[1] + R[r][2] * off_mm[2] + t_mm[r];
        direction_[i][r] = float(d);
        offset_m_[i][r] = float(o * 1e-3);
      }
    }
  }
  std::vector<int> order(std::size_t(h), 0);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return meta_.beam_altitude_deg[std::size_t(a)] < meta_.beam_altitude_deg[std::size_t(b)];
  });
  ring_of_beam_.resize(std::size_t(h));
  for (int r = 0; r < h; ++r) ring_of_beam_[std::size_t(order[std::size_t(r)])] = std::uint16_t(r);
}

void OusterDecoder::decode(std::span<const std::uint8_t> bytes, std::vector<OusterColumn>& columns,
                           std::vector<Point>& points) const {
  const auto& m = meta_;
  if (bytes.size() != packet_bytes_)
    throw Error("Ouster lidar packet has " + std::to_string(bytes.size()) +
                " bytes but the metadata (" + to_string(m.profile) + ", " +
                std::to_string(m.pixels_per_column) + " beams, " +
                std::to_string(m.columns_per_packet) + " columns per packet) implies " +
                std::to_string(packet_bytes_) + ": the metadata does not belong to this capture");
  const std::size_t h = std::size_t(m.pixels_per_column);
  const std::size_t ncol = std::size_t(m.columns_per_packet);
  columns.resize(ncol);
  points.resize(ncol * h);
  const std::uint8_t* p = bytes.data();
  const bool legacy = m.profile == OusterProfile::kLegacy;
  std::uint16_t packet_frame_id = 0;
  if (!legacy) {
    const std::uint16_t type = le16(p);
    if (type != 1)
      throw Error("Ouster packet type " + std::to_string(type) + " is not lidar data (1)");
    packet_frame_id = le16(p + 2);
    const std::uint32_t init_id =
        std::uint32_t(p[4]) | std::uint32_t(p[5]) << 8 | std::uint32_t(p[6]) << 16;
    if (m.initialization_id && *m.initialization_id != init_id)
      throw Error("Ouster packet initialization id " + std::to_string(init_id) +
                  " differs from the metadata's " + std::to_string(*m.initialization_id) +
                  ": the metadata does not belong to this capture");
    std::uint64_t serial = 0;
    for (int k = 4; k >= 0; --k) serial = (serial << 8) | p[7 + k];
    if (!m.prod_sn.empty() && serial != 0 && std::to_string(serial) != m.prod_sn)
      throw Error("Ouster packet serial number " + std::to_string(serial) +
                  " differs from the metadata's " + m.prod_sn +
                  ": the metadata does not belong to this capture");
    p += kRngPacketHeader;
  }
  const std::size_t col_bytes = legacy
                                    ? kLegacyColumnHeader + h * kChannelBytes + kLegacyColumnFooter
                                    : kRngColumnHeader + h * kChannelBytes;
  for (std::size_t c = 0; c < ncol; ++c) {
    const std::uint8_t* col = p + c * col_bytes;
    OusterColumn& oc = columns[c];
    oc.timestamp_ns = le64(col);
    oc.measurement_id = le16(col + 8);
    oc.frame_id = legacy ? le16(col + 10) : packet_frame_id;
    oc.valid = legacy ? le32(col + kLegacyColumnHeader + h * kChannelBytes) == 0xFFFFFFFFu
                      : (le16(col + 10) & 1u) != 0;
    if (oc.valid && oc.measurement_id >= m.columns_per_frame)
      throw Error("Ouster column measurement id " + std::to_string(oc.measurement_id) +
                  " is not below columns_per_frame = " + std::to_string(m.columns_per_frame) +
                  ": the metadata does not belong to this capture");
    const std::uint8_t* ch = col + (legacy ? kLegacyColumnHeader : kRngColumnHeader);
    Point* out = points.data() + c * h;
    if (!oc.valid) {
      std::fill(out, out + h, Point{});
      continue;
    }
    const std::size_t lut = std::size_t(oc.measurement_id) * h;
    for (std::size_t b = 0; b < h; ++b, ch += kChannelBytes) {
      const std::uint32_t range_mm = le32(ch) & (legacy ? 0xFFFFFu : 0x7FFFFu);
      Point& pt = out[b];
      pt = Point{};
      pt.ring = ring_of_beam_[b];
      pt.intensity = float(le16(ch + 6));  // signal photons (both profiles)
      if (range_mm == 0) continue;         // no return: all-zero point
      const Eigen::Vector3f xyz =
          direction_[lut + b] * (float(range_mm) * 1e-3f) + offset_m_[lut + b];
      pt.x = xyz.x();
      pt.y = xyz.y();
      pt.z = xyz.z();
    }
  }
}

OusterImuSample decode_ouster_imu_packet(std::span<const std::uint8_t> bytes) {
  if (bytes.size() != kImuPacketBytes)
    throw Error("Ouster IMU packet has " + std::to_string(bytes.size()) + " bytes, expected 48");
  const std::uint8_t* p = bytes.data();
  OusterImuSample s;
  s.stamp_s = double(le64(p + 16)) * 1e-9;  // gyro read time, sensor clock
  constexpr double kG = 9.80665;
  constexpr double kDeg = std::numbers::pi / 180.0;
  for (int k = 0; k < 3; ++k) {
    s.accel_m_s2[k] = double(lef32(p + 24 + 4 * k)) * kG;
    s.gyro_rad_s[k] = double(lef32(p + 36 + 4 * k)) * kDeg;
  }
  return s;
}

void OusterFrameAssembler::start_frame(std::uint16_t frame_id) {
  const auto& m = decoder_.metadata();
  const std::size_t w = std::size_t(m.columns_per_frame), h = std::size_t(m.pixels_per_column);
  open_ = true;
  frame_id_ = frame_id;
  column_ts_.assign(w, 0);
  frame_points_.assign(w * h, Point{});
}

void OusterFrameAssembler::close_frame() {
  if (!open_) return;
  open_ = false;
  const auto& m = decoder_.metadata();
  const std::size_t w = std::size_t(m.columns_per_frame), h = std::size_t(m.pixels_per_column);
  OusterFrame f;
  f.frame_id = frame_id_;
  std::uint64_t t0 = 0;
  for (std::size_t c = 0; c < w; ++c)
    if (column_ts_[c] != 0) {
      ++f.columns_received;
      if (t0 == 0 || column_ts_[c] < t0) t0 = column_ts_[c];
    }
  const int first = m.column_window_first, last = m.column_window_last;
  const std::size_t window =
      std::size_t(last >= first ? last - first + 1 : (int(w) - first) + last + 1);
  f.complete = f.columns_received >= window;
  for (std::size_t r = 0; r < h; ++r)
    for (std::size_t c = 0; c < w; ++c) {
      Point& p = frame_points_[r * w + c];
      p.ring = std::uint16_t(r);
      if (column_ts_[c] != 0) p.time = float(double(column_ts_[c] - t0) * 1e-9);
    }
  f.cloud.points = std::move(frame_points_);
  frame_points_ = {};
  f.cloud.width = std::uint32_t(w);
  f.cloud.height = std::uint32_t(h);
  f.cloud.stamp_s = double(t0) * 1e-9;
  f.cloud.fields.intensity = f.cloud.fields.ring = f.cloud.fields.time = true;
  ready_.push_back(std::move(f));
}

void OusterFrameAssembler::add_packet(std::span<const std::uint8_t> bytes,
                                      const std::string& source) {
  const std::size_t packet = packets_++;
  try {
    decoder_.decode(bytes, columns_, points_);
  } catch (const Error& e) {
    throw Error(source + ": lidar packet " + std::to_string(packet) + ": " + e.what());
  }
  const std::size_t w = std::size_t(decoder_.metadata().columns_per_frame);
  const std::size_t h = std::size_t(decoder_.metadata().pixels_per_column);
  for (std::size_t c = 0; c < columns_.size(); ++c) {
    const OusterColumn& col = columns_[c];
    if (!col.valid) continue;
    if (!open_)
      start_frame(col.frame_id);
    else if (col.frame_id != frame_id_) {
      close_frame();
      start_frame(col.frame_id);
    }
    const std::size_t mid = col.measurement_id;
    column_ts_[mid] = std::max<std::uint64_t>(col.timestamp_ns, 1);
    for (std::size_t b = 0; b < h; ++b) {
      const Point& src = points_[c * h + b];
      frame_points_[std::size_t(src.ring) * w + mid] = src;
    }
  }
}

void OusterFrameAssembler::finish() {
  close_frame();
}

std::optional<OusterFrame> OusterFrameAssembler::pop() {
  if (ready_.empty()) return std::nullopt;
  OusterFrame f = std::move(ready_.front());
  ready_.pop_front();
  return f;
}

}  // namespace fieldlidar::io
