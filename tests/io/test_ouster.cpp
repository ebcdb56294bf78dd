// Ouster decoding: metadata layouts, real captures into sane frames, wrong metadata.
#include <cmath>
#include <cstring>
#include <fstream>
#include <numbers>

#include <gtest/gtest.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/frame_source.hpp"
#include "fieldlidar/io/ouster.hpp"
#include "sweep_checks.hpp"
#include "test_data.hpp"

namespace fieldlidar {
namespace {

const char* kOs1 = "ouster_pcap/OS-1-64_1024x10_fw20.pcap";
const char* kOs1Meta = "ouster_pcap/2_0_0_os1-991913000010-64.json";
const char* kOs1Reduced = "ouster_pcap/OS-1-64_sensor_config_reduced.json";
const char* kOs2 = "ouster_pcap/OS-2-128-U1_v2.3.0_1024x10.pcap";
const char* kOs2Meta = "ouster_pcap/OS-2-128-U1_v2.3.0_1024x10.json";

std::vector<io::Frame> decode(const char* pcap, const char* meta, std::size_t beams) {
  io::SourceOptions o;
  if (meta) o.metadata = test::data_file(meta);
  auto src = io::FrameSource::open(test::data_file(pcap), o);
  EXPECT_EQ(src->format(), "ouster-pcap");
  EXPECT_TRUE(src->sensor() && src->sensor()->rings() == beams);
  std::vector<io::Frame> frames;
  while (auto f = src->next()) frames.push_back(std::move(*f));
  // The capture's IMU packets come through too (11 and 10 in these files).
  EXPECT_GE(src->imu_until(1e18).size(), 10u);
  return frames;
}

/// Organized frame checks: rows = rings, column times follow the column index at 10 Hz, every
/// valid point's azimuth matches its column's encoder angle, ranges within the sensor limits.
void check_frame(const io::Frame& f, std::size_t beams, double max_range_m) {
  const auto& c = f.cloud;
  ASSERT_TRUE(f.complete);
  ASSERT_EQ(c.height, beams);
  ASSERT_EQ(c.width, 1024u);
  EXPECT_EQ(c.ring_count(), beams);
  std::size_t valid = 0, beyond = 0;
  for (std::size_t r = 0; r < c.height; ++r)
    for (std::size_t col = 0; col < c.width; ++col) {
      const Point& p = c.points[r * c.width + col];
      ASSERT_EQ(p.ring, r);
      // 1024 columns per 0.1 s turn.
      ASSERT_NEAR(p.time, col * 0.1 / 1024, 2e-4) << "column " << col;
      if (!p.is_valid()) continue;
      ++valid;
      const double range = std::sqrt(double(p.x) * p.x + double(p.y) * p.y + double(p.z) * p.z);
      ASSERT_GT(range, 0.2);
      beyond += range > max_range_m;
      if (range < 2.0) continue;  // the beam-origin offset dominates the angle up close
      // Sensor frame (x forward, after lidar_to_sensor's 180-deg turn): column c looks at
      // azimuth pi - 2 pi c / 1024, to within the beam azimuth offsets (< 5 deg).
      const double expect = std::numbers::pi - 2 * std::numbers::pi * col / 1024.0;
      double d = std::atan2(p.y, p.x) - expect;
      d = std::remainder(d, 2 * std::numbers::pi);
      ASSERT_LT(std::abs(d), 5.0 * std::numbers::pi / 180) << "ring " << r << " column " << col;
    }
  EXPECT_GT(valid, c.size() / 5);
  EXPECT_LT(double(beyond), 1e-3 * double(valid));  // a few specular returns beyond spec
}

TEST(Ouster, Os1LegacyFirmware20CaptureDecodes) {
  FIELDLIDAR_REQUIRE_DATA(kOs1);
  FIELDLIDAR_REQUIRE_DATA(kOs1Meta);
  const auto frames = decode(kOs1, kOs1Meta, 64);
  ASSERT_EQ(frames.size(), 1u);
  check_frame(frames[0], 64, 120.0);
  EXPECT_EQ(frames[0].cloud.valid_count(), 16749u);  // a small room: most beams see nothing
  // Flat surfaces: rings 16-19 in 20-deg sectors; measured median 9.3 mm.
  const auto rms = test::sector_plane_rms(frames[0].cloud, 16, 19, 20.0, 20.0);
  ASSERT_GE(rms.size(), 5u);
  EXPECT_LT(rms[rms.size() / 2], 0.02);
}

TEST(Ouster, Os1ReducedFlatMetadataAlsoReads) {
  FIELDLIDAR_REQUIRE_DATA(kOs1);
  FIELDLIDAR_REQUIRE_DATA(kOs1Reduced);
  // Flat layout with only the beam angles and mode: the OS-1 defaults fill the rest.
  const auto meta = io::read_ouster_metadata(test::data_file(kOs1Reduced));
  EXPECT_EQ(meta.pixels_per_column, 64);
  EXPECT_DOUBLE_EQ(meta.lidar_origin_to_beam_origin_mm, 12.163);
  const auto frames = decode(kOs1, kOs1Reduced, 64);
  ASSERT_EQ(frames.size(), 1u);
  check_frame(frames[0], 64, 120.0);
}

TEST(Ouster, NestedAndFlatLayoutsParse) {
  FIELDLIDAR_REQUIRE_DATA(kOs1Meta);
  FIELDLIDAR_REQUIRE_DATA(kOs2Meta);
  const auto nested = io::read_ouster_metadata(test::data_file(kOs1Meta));
  EXPECT_EQ(nested.prod_line, "OS-1-64");
  EXPECT_EQ(nested.profile, io::OusterProfile::kLegacy);
  EXPECT_EQ(nested.columns_per_frame, 1024);
  EXPECT_NEAR(nested.beam_altitude_deg[0], 16.729, 1e-9);
  EXPECT_NEAR(nested.lidar_to_sensor_transform(0, 0), -1.0, 1e-12);
  EXPECT_EQ(io::ouster_lidar_packet_bytes(nested), 12608u);
  const auto flat = io::read_ouster_metadata(test::data_file(kOs2Meta));
  EXPECT_EQ(flat.prod_line, "OS-2-128");
  EXPECT_EQ(flat.profile, io::OusterProfile::kRng19Rfl8Sig16Nir16);
  EXPECT_NEAR(flat.lidar_origin_to_beam_origin_mm, 13.762, 1e-9);
  EXPECT_EQ(io::ouster_lidar_packet_bytes(flat), 24832u);
  // Ring 0 is the lowest beam: SensorModel altitudes ascend.
  const auto model = io::sensor_model_of(flat);
  EXPECT_LT(model.beam_altitudes_rad.front(), model.beam_altitudes_rad.back());
  EXPECT_THROW(io::parse_ouster_metadata("{\"beam_altitude_angles\": [1, 2]}", "x.json"), Error);
  EXPECT_THROW(io::parse_ouster_metadata("not json", "x.json"), Error);
}

TEST(Ouster, Os2Rng19CaptureDecodesWithSidecarMetadata) {
  FIELDLIDAR_REQUIRE_DATA(kOs2);
  FIELDLIDAR_REQUIRE_DATA(kOs2Meta);
  const auto frames = decode(kOs2, nullptr, 128);  // <capture>.json found beside it
  ASSERT_EQ(frames.size(), 1u);
  check_frame(frames[0], 128, 240.0);
  EXPECT_GT(frames[0].cloud.valid_count(), 100000u);
  // Ground below the sensor: rings 0-3 in 20-deg sectors; measured q25 13 mm, median 27 mm.
  const auto rms = test::sector_plane_rms(frames[0].cloud, 0, 3, 20.0, 20.0);
  ASSERT_GE(rms.size(), 12u);
  EXPECT_LT(rms[rms.size() / 4], 0.02);
  EXPECT_LT(rms[rms.size() / 2], 0.04);
}

TEST(Ouster, WrongMetadataGivesAClearError) {
  FIELDLIDAR_REQUIRE_DATA(kOs2);
  FIELDLIDAR_REQUIRE_DATA(kOs1Meta);
  io::SourceOptions o;
  o.metadata = test::data_file(kOs1Meta);  // a 64-beam LEGACY sensor for a 128-beam RNG19 capture
  auto src = io::FrameSource::open(test::data_file(kOs2), o);
  try {
    while (src->next()) {
    }
    FAIL() << "wrong metadata must be refused";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("does not belong to this capture"), std::string::npos)
        << e.what();
  }
  // The OS-1 capture with the OS-2 metadata: sizes differ too.
  o.metadata = test::data_file(kOs2Meta);
  auto src2 = io::FrameSource::open(test::data_file(kOs1), o);
  EXPECT_THROW(
      {
        while (src2->next()) {
        }
      },
      Error);
}

TEST(Ouster, PacketDecoderChecksSizeIdsAndInitId) {
  FIELDLIDAR_REQUIRE_DATA(kOs2Meta);
  auto meta = io::read_ouster_metadata(test::data_file(kOs2Meta));
  io::OusterDecoder dec(meta);
  std::vector<std::uint8_t> pkt(dec.packet_bytes(), 0);
  std::vector<io::OusterColumn> cols;
  std::vector<Point> pts;
  EXPECT_THROW(dec.decode(std::span(pkt).first(100), cols, pts), Error);
  pkt[0] = 1;  // lidar packet type
  const std::uint32_t init = *meta.initialization_id;
  pkt[4] = std::uint8_t(init), pkt[5] = std::uint8_t(init >> 8), pkt[6] = std::uint8_t(init >> 16);
  // One valid column, id 5, one beam at 10 m.
  const std::size_t col0 = 32;
  pkt[col0 + 8] = 5;
  pkt[col0 + 10] = 1;
  const std::uint32_t range_mm = 10000;
  std::memcpy(&pkt[col0 + 12], &range_mm, 4);
  dec.decode(pkt, cols, pts);
  EXPECT_TRUE(cols[0].valid);
  EXPECT_FALSE(cols[1].valid);
  EXPECT_EQ(cols[0].measurement_id, 5);
  EXPECT_NEAR(pts[0].xyz().norm(), 10.0, 0.06);  // + beam origin offset and 36 mm height
  pkt[6] ^= 0x40;
  EXPECT_THROW(dec.decode(pkt, cols, pts), Error);
}

}  // namespace
}  // namespace fieldlidar
