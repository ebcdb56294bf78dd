// Velodyne decoding: real captures into sane sweeps, flat ground, corrupt packets and captures.
#include <cmath>
#include <fstream>
#include <vector>

#include <gtest/gtest.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/frame_source.hpp"
#include "fieldlidar/io/velodyne.hpp"
#include "sweep_checks.hpp"
#include "test_data.hpp"

namespace fieldlidar {
namespace {

struct CaptureStats {
  std::size_t complete = 0, partial = 0;
  std::vector<io::Frame> frames;
  std::optional<SensorModel> sensor;
};

CaptureStats decode_all(const std::string& rel) {
  CaptureStats s;
  auto src = io::FrameSource::open(test::data_file(rel));
  EXPECT_EQ(src->format(), "velodyne-pcap");
  s.sensor = src->sensor();
  while (auto f = src->next()) {
    (f->complete ? s.complete : s.partial) += 1;
    s.frames.push_back(std::move(*f));
  }
  return s;
}

/// Rings, time, range and coverage of every sweep of a capture.
void check_sweeps(const CaptureStats& s, std::size_t beams) {
  ASSERT_TRUE(s.sensor);
  ASSERT_EQ(s.sensor->rings(), beams);
  const double period_s = 1.0 / 5.0;  // slowest Velodyne setting (300 rpm) bounds any sweep
  for (const auto& f : s.frames) {
    const auto& c = f.cloud;
    ASSERT_GT(c.size(), 1000u) << "frame " << f.index;
    EXPECT_TRUE(c.fields.ring && c.fields.time && c.fields.intensity);
    EXPECT_EQ(c.ring_count(), beams) << "frame " << f.index;
    float tmax = 0;
    for (const auto& p : c.points) {
      ASSERT_LT(p.ring, beams);
      ASSERT_GE(p.time, 0.f);
      tmax = std::max(tmax, p.time);
      const double r = std::sqrt(double(p.x) * p.x + double(p.y) * p.y + double(p.z) * p.z);
      // Velodyne's 16-bit distance field ends at 131 m (2 mm units); returns come from > 0.3 m.
      ASSERT_GT(r, 0.3);
      ASSERT_LT(r, 1.1 * s.sensor->max_range_m) << "frame " << f.index;
    }
    EXPECT_LT(tmax, period_s);
    if (f.complete) {
      EXPECT_GE(test::azimuth_coverage_deg(c), 355.0) << "frame " << f.index;
    }
  }
}

TEST(Velodyne, Vlp16CaptureDecodesIntoSweepsWith16Rings) {
  FIELDLIDAR_REQUIRE_DATA("velodyne_pcap/velodyne_example.pcap");
  const auto s = decode_all("velodyne_pcap/velodyne_example.pcap");
  EXPECT_EQ(s.sensor->name, "vlp16");
  // 84 packets (~0.11 s) starting mid-turn: two partial sweeps, no full turn in between.
  EXPECT_EQ(s.complete, 0u);
  EXPECT_EQ(s.partial, 2u);
  check_sweeps(s, 16);
  // The two parts together cover the full circle once.
  PointCloud both = s.frames[0].cloud;
  both.points.insert(both.points.end(), s.frames[1].cloud.points.begin(),
                     s.frames[1].cloud.points.end());
  EXPECT_GE(test::azimuth_coverage_deg(both), 355.0);
}

TEST(Velodyne, Hdl32CaptureHasFiveFullSweepsAtItsRotationPeriod) {
  FIELDLIDAR_REQUIRE_DATA("velodyne_pcap/hdl32_example.pcap");
  const auto s = decode_all("velodyne_pcap/hdl32_example.pcap");
  EXPECT_EQ(s.sensor->name, "hdl32e");
  EXPECT_EQ(s.complete, 5u);
  EXPECT_EQ(s.partial, 2u);
  check_sweeps(s, 32);
  // Consecutive full sweeps are one rotation apart and their last firing closes the turn.
  for (std::size_t i = 1; i + 2 < s.frames.size(); ++i) {
    const double period = s.frames[i + 1].stamp_s - s.frames[i].stamp_s;
    EXPECT_NEAR(period, 0.0853, 0.002);
    float tmax = 0;
    for (const auto& p : s.frames[i].cloud.points) tmax = std::max(tmax, p.time);
    EXPECT_NEAR(tmax, period, 0.001);
    // HDL-32E single return: 1 return per laser per 46.08 µs firing.
    EXPECT_GT(s.frames[i].cloud.size(), std::size_t(0.6 * 32 * period / 46.08e-6));
  }
}

TEST(Velodyne, GroundPatchesAreFlat) {
  // Rings 0-3 of the HDL-32E (-30.7 to -26.7 deg) reach the road 3-5 m around the car; a 20-deg
  // sector of them is a 1-2 m patch spanning four beams, flat only when elevations, ring order,
  // range scale and azimuth interpolation are right. Measured median RMS: 4.6 mm (hdl32_example),
  // 4.6 mm (velodyne_vlp32).
  for (const char* rel :
       {"velodyne_pcap/hdl32_example.pcap", "velodyne_pcap/velodyne_vlp32.pcap"}) {
    FIELDLIDAR_REQUIRE_DATA(rel);
    const auto s = decode_all(rel);
    const auto rms = test::sector_plane_rms(s.frames.front().cloud, 0, 3, 20.0, 20.0);
    ASSERT_GE(rms.size(), 6u) << rel;
    EXPECT_LT(rms[rms.size() / 2], 0.01) << rel;
  }
  // VLP-16 indoors: rings 4-7 on the floor; measured best sector 7.4 mm.
  FIELDLIDAR_REQUIRE_DATA("velodyne_pcap/velodyne_example.pcap");
  const auto s = decode_all("velodyne_pcap/velodyne_example.pcap");
  const auto rms = test::sector_plane_rms(s.frames.front().cloud, 4, 7, 20.0, 20.0);
  ASSERT_GE(rms.size(), 2u);
  EXPECT_LT(rms[0], 0.01);
  EXPECT_LT(rms[1], 0.02);
}

TEST(Velodyne, Vlp32FileIsAnHdl32ePartialTurn) {
  FIELDLIDAR_REQUIRE_DATA("velodyne_pcap/velodyne_vlp32.pcap");
  const auto s = decode_all("velodyne_pcap/velodyne_vlp32.pcap");
  EXPECT_EQ(s.sensor->name, "hdl32e");  // model byte 0x21
  EXPECT_EQ(s.complete, 0u);            // 91 data packets: about half a turn
  EXPECT_EQ(s.partial, 2u);
  check_sweeps(s, 32);
}

std::vector<std::uint8_t> synthetic_packet(std::uint8_t model_byte, std::uint8_t mode_byte) {
  std::vector<std::uint8_t> p(io::kVelodyneDataPacketBytes, 0);
  for (int b = 0; b < 12; ++b) {
    p[std::size_t(b * 100)] = 0xFF;
    p[std::size_t(b * 100 + 1)] = 0xEE;
    const int az = 1000 + b * 40;  // 0.4 deg per block
    p[std::size_t(b * 100 + 2)] = std::uint8_t(az & 0xFF);
    p[std::size_t(b * 100 + 3)] = std::uint8_t(az >> 8);
    for (int c = 0; c < 32; ++c) {
      const std::size_t o = std::size_t(b * 100 + 4 + c * 3);
      p[o] = 0xE8;  // 1000 units = 2 m (4 m on the VLP-32C)
      p[o + 1] = 0x03;
      p[o + 2] = 100;
    }
  }
  p[1204] = mode_byte;
  p[1205] = model_byte;
  return p;
}

TEST(Velodyne, PacketGeometryMatchesTheLaserTable) {
  std::vector<io::VelodyneReturn> out;
  const auto info = io::decode_velodyne_packet(synthetic_packet(0x22, 0x37), out);
  EXPECT_EQ(info.model, io::VelodyneModel::kVlp16);
  ASSERT_EQ(out.size(), 384u);
  // Channel 0 = laser 0 at -15 deg, 2 m: z = 2 sin(-15 deg) + 11.2 mm, ring 0; laser 1 (+1 deg) is
  // ring 8; second firing sequence of block 0 is 55.296 µs later.
  EXPECT_NEAR(out[0].point.z, 2.0 * std::sin(-15.0 * M_PI / 180) + 0.0112, 1e-4);
  EXPECT_NEAR(std::hypot(out[0].point.x, out[0].point.y), 2.0 * std::cos(15.0 * M_PI / 180), 1e-4);
  EXPECT_EQ(out[0].point.ring, 0);
  EXPECT_EQ(out[1].point.ring, 8);
  EXPECT_EQ(out[15].point.ring, 15);
  EXPECT_NEAR(out[16].point.time, 55.296e-6, 1e-9);
  EXPECT_NEAR(out[32].point.time, 110.592e-6, 1e-9);
  // Azimuth 10 deg, clockwise: y < 0.
  EXPECT_NEAR(std::atan2(-out[0].point.y, out[0].point.x) * 180 / M_PI, 10.0, 0.02);

  out.clear();
  EXPECT_EQ(io::decode_velodyne_packet(synthetic_packet(0x28, 0x39), out).mode,
            io::VelodyneReturnMode::kDual);
  // VLP-32C: 4 mm units.
  EXPECT_NEAR(std::sqrt(out[0].point.x * out[0].point.x + out[0].point.y * out[0].point.y +
                        out[0].point.z * out[0].point.z),
              4.0, 1e-3);
}

TEST(Velodyne, Hdl64eUpperAndLowerBlocksAndDualReturnTiming) {
  // HDL-64E: blocks alternate upper (0xEEFF, lasers 0-31) and lower (0xDDFF, lasers 32-63) at
  // one azimuth per pair; there is no model byte.
  auto p = synthetic_packet(0x00, 0x00);
  for (int b = 0; b < 12; ++b) {
    p[std::size_t(b * 100 + 1)] = (b % 2) ? 0xDD : 0xEE;
    const int az = 2000 + (b / 2) * 20;
    p[std::size_t(b * 100 + 2)] = std::uint8_t(az & 0xFF);
    p[std::size_t(b * 100 + 3)] = std::uint8_t(az >> 8);
  }
  std::vector<io::VelodyneReturn> out;
  EXPECT_EQ(io::decode_velodyne_packet(p, out).model, io::VelodyneModel::kHdl64e);
  ASSERT_EQ(out.size(), 384u);
  EXPECT_EQ(out[0].point.ring, 63);                        // upper laser 0, +2 deg: highest
  EXPECT_EQ(out[31].point.ring, 32);                       // upper laser 31, -8.33 deg
  EXPECT_EQ(out[32].point.ring, 31);                       // lower laser 32, -8.83 deg
  EXPECT_EQ(out[63].point.ring, 0);                        // lower laser 63, -24.33 deg
  EXPECT_FLOAT_EQ(out[32].point.time, out[0].point.time);  // the pair fires together
  EXPECT_NEAR(out[64].point.time, 48e-6, 1e-9);            // next firing

  // VLP-16 dual return: block pairs share the azimuth and the firing time.
  auto d = synthetic_packet(0x22, 0x39);
  for (int b = 0; b < 12; ++b) {
    const int az = 1000 + (b / 2) * 40;
    d[std::size_t(b * 100 + 2)] = std::uint8_t(az & 0xFF);
    d[std::size_t(b * 100 + 3)] = std::uint8_t(az >> 8);
  }
  out.clear();
  EXPECT_EQ(io::decode_velodyne_packet(d, out).mode, io::VelodyneReturnMode::kDual);
  EXPECT_FLOAT_EQ(out[32].point.time, out[0].point.time);
  EXPECT_NEAR(out[64].point.time, 110.592e-6, 1e-9);
}

TEST(Velodyne, BadPacketsGiveClearErrors) {
  std::vector<io::VelodyneReturn> out;
  auto short_packet = synthetic_packet(0x22, 0x37);
  short_packet.resize(1000);
  EXPECT_THROW(io::decode_velodyne_packet(short_packet, out), Error);
  try {
    io::decode_velodyne_packet(synthetic_packet(0x99, 0x37), out);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("0x99"), std::string::npos) << e.what();
  }
  auto bad_flag = synthetic_packet(0x22, 0x37);
  bad_flag[500] = 0x12;
  EXPECT_THROW(io::decode_velodyne_packet(bad_flag, out), Error);
  auto bad_az = synthetic_packet(0x22, 0x37);
  bad_az[2] = 0xFF, bad_az[3] = 0xFF;
  EXPECT_THROW(io::decode_velodyne_packet(bad_az, out), Error);
  // A capture switching sensors mid-stream is refused.
  io::VelodyneSweepAssembler a;
  a.add_packet(synthetic_packet(0x22, 0x37), 0.0, "test");
  EXPECT_THROW(a.add_packet(synthetic_packet(0x21, 0x37), 0.001, "test"), Error);
}

// A capture cut mid-record (recorder killed) is read up to the cut and says so (warnings()).
TEST(Velodyne, TruncatedCaptureEndsAtTheCutWithAWarning) {
  FIELDLIDAR_REQUIRE_DATA("velodyne_pcap/hdl32_example.pcap");
  const auto dir = test::temp_dir("velodyne_truncated");
  std::ifstream in(test::data_file("velodyne_pcap/hdl32_example.pcap"), std::ios::binary);
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), {});
  bytes.resize(bytes.size() / 2 + 333);
  const auto path = dir / "cut.pcap";
  std::ofstream(path, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
  auto src = io::FrameSource::open(path);
  std::size_t complete = 0;
  while (auto f = src->next()) complete += f->complete;
  EXPECT_EQ(complete, 2u);  // of 5 in the whole capture
  const auto warnings = src->warnings();
  ASSERT_EQ(warnings.size(), 1u);  // must not end quietly
  EXPECT_NE(warnings[0].find("cut.pcap"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[0].find("truncated"), std::string::npos) << warnings[0];
}

}  // namespace
}  // namespace fieldlidar
