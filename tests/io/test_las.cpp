#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <vector>

#include <gtest/gtest.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/las.hpp"
#include "test_data.hpp"

using namespace fieldlidar;

namespace {

struct SynthPoint {
  double x, y, z, gps;
  std::uint16_t intensity;
  std::uint8_t cls;
};

template <typename T>
void put(std::vector<std::byte>& b, std::size_t at, T v) {
  std::memcpy(b.data() + at, &v, sizeof(T));
}

/// A LAS file built byte by byte from the specification (header fields at their table offsets).
std::vector<std::byte> make_las(std::uint8_t minor, std::uint8_t format,
                                const std::vector<SynthPoint>& pts, Eigen::Vector3d scale,
                                Eigen::Vector3d offset, std::uint16_t extra_bytes = 0) {
  const std::size_t header = minor >= 4 ? 375 : minor == 3 ? 235 : 227;
  const std::size_t rec = io::las_point_size(format) + extra_bytes;
  std::vector<std::byte> b(header + rec * pts.size());
  std::memcpy(b.data(), "LASF", 4);
  put<std::uint8_t>(b, 24, 1);
  put<std::uint8_t>(b, 25, minor);
  put<std::uint16_t>(b, 94, static_cast<std::uint16_t>(header));
  put<std::uint32_t>(b, 96, static_cast<std::uint32_t>(header));
  put<std::uint8_t>(b, 104, format);
  put<std::uint16_t>(b, 105, static_cast<std::uint16_t>(rec));
  put<std::uint32_t>(b, 107, format >= 6 ? 0u : static_cast<std::uint32_t>(pts.size()));
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  for (const auto& p : pts) {
    lo = lo.cwiseMin(Eigen::Vector3d(p.x, p.y, p.z));
    hi = hi.cwiseMax(Eigen::Vector3d(p.x, p.y, p.z));
  }
  for (int a = 0; a < 3; ++a) {
    put<double>(b, 131 + 8 * a, scale[a]);
    put<double>(b, 155 + 8 * a, offset[a]);
    put<double>(b, 179 + 16 * a, hi[a]);
    put<double>(b, 187 + 16 * a, lo[a]);
  }
  if (minor >= 4) put<std::uint64_t>(b, 247, pts.size());
  const bool ext = format >= 6;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const std::size_t at = header + i * rec;
    const auto& p = pts[i];
    put<std::int32_t>(b, at + 0,
                      static_cast<std::int32_t>(std::lround((p.x - offset[0]) / scale[0])));
    put<std::int32_t>(b, at + 4,
                      static_cast<std::int32_t>(std::lround((p.y - offset[1]) / scale[1])));
    put<std::int32_t>(b, at + 8,
                      static_cast<std::int32_t>(std::lround((p.z - offset[2]) / scale[2])));
    put<std::uint16_t>(b, at + 12, p.intensity);
    // formats 0-5: the flag bits 5-7 (synthetic, key point, withheld) must not leak into the class
    put<std::uint8_t>(b, at + (ext ? 16 : 15),
                      ext ? p.cls : static_cast<std::uint8_t>(p.cls | 0x80));
    if (format == 1 || format >= 3) put<double>(b, at + (ext ? 22 : 20), p.gps);
  }
  return b;
}

std::vector<SynthPoint> utm_points() {
  // A projected-frame patch (UTM-like, x ~ 5e5 m, y ~ 5.3e6 m) that float32 alone would blur.
  std::vector<SynthPoint> pts;
  for (int i = 0; i < 50; ++i)
    pts.push_back({512345.678 + 0.123 * i, 5301234.567 - 0.071 * i, 812.345 + 0.01 * i,
                   3.0e8 + 0.001 * i, static_cast<std::uint16_t>(100 + i),
                   static_cast<std::uint8_t>(i % 3 == 0 ? 2 : 1)});
  return pts;
}

}  // namespace

TEST(Las, EveryPointFormatAndVersionDecodes) {
  const auto pts = utm_points();
  for (std::uint8_t minor : {2, 3, 4}) {
    for (std::uint8_t format = 0; format <= 10; ++format) {
      if (format >= 6 && minor < 4) continue;  // formats 6-10 are LAS 1.4 only
      SCOPED_TRACE("LAS 1." + std::to_string(minor) + " format " + std::to_string(format));
      const auto bytes = make_las(minor, format, pts, {0.001, 0.001, 0.001}, {500000, 5300000, 0},
                                  format == 3 ? 7 : 0);
      const auto las = io::parse_las(bytes, "synthetic.las");
      ASSERT_EQ(las.cloud.size(), pts.size());
      EXPECT_EQ(las.header.point_count, pts.size());
      EXPECT_EQ(las.origin_m, Eigen::Vector3d(512000, 5301000, 0));
      const bool gps = format == 1 || format >= 3;
      EXPECT_EQ(las.cloud.fields.time, gps);
      if (gps) {
        EXPECT_DOUBLE_EQ(las.cloud.stamp_s, 3.0e8);
      }
      for (std::size_t i = 0; i < pts.size(); ++i) {
        const auto& p = las.cloud.points[i];
        EXPECT_NEAR(p.x + las.origin_m.x(), pts[i].x, 1e-3);  // 1 mm scale, float32 near 1 km
        EXPECT_NEAR(p.y + las.origin_m.y(), pts[i].y, 1e-3);
        EXPECT_NEAR(p.z + las.origin_m.z(), pts[i].z, 1e-3);
        EXPECT_EQ(p.intensity, pts[i].intensity);
        EXPECT_EQ(las.cloud.labels[i], pts[i].cls);
        if (gps) {
          EXPECT_NEAR(p.time, 0.001 * i, 1e-6);
        }
      }
    }
  }
}

TEST(Las, CompressedAndLazAreRefusedWithAClearMessage) {
  auto bytes = make_las(2, 1, utm_points(), {0.01, 0.01, 0.01}, {0, 0, 0});
  bytes[104] = std::byte{0x81};  // LAZ sets bit 7 of the point format id
  try {
    io::parse_las(bytes, "x.las");
    FAIL() << "a compressed LAS was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("compressed LAZ is not supported, decompress it first"),
              std::string::npos)
        << e.what();
  }
  // Format 99 has neither the LAZ bit 7 nor a format 0-10 under bit 6: it is no format at all.
  bytes[104] = std::byte{99};
  try {
    io::parse_las(bytes, "x.las");
    FAIL() << "point data format 99 was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("point data format 99 is invalid (LAS defines 0-10"),
              std::string::npos)
        << e.what();
  }
  const auto dir = test::temp_dir("las_laz");
  std::ofstream(dir / "a.laz") << "LASF";
  try {
    io::read_las(dir / "a.laz");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("decompress it first"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("a.laz"), std::string::npos);
  }
}

TEST(Las, HeaderFieldsThatDoNotFitTheFileAreErrors) {
  const auto good = make_las(4, 6, utm_points(), {0.001, 0.001, 0.001}, {500000, 5300000, 0});
  auto expect_error = [](std::vector<std::byte> b, const char* what) {
    SCOPED_TRACE(what);
    EXPECT_THROW(io::parse_las(b, "bad.las"), Error);
  };
  auto b = good;
  put<std::uint64_t>(b, 247, 1000000000000ull);  // count far beyond the file
  expect_error(b, "count");
  b = good;
  put<std::uint16_t>(b, 105, 10);  // record shorter than format 6
  expect_error(b, "record length");
  b = good;
  put<std::uint32_t>(b, 96, 0xFFFFFFF0u);  // point data offset past the end
  expect_error(b, "offset");
  b = good;
  put<std::uint16_t>(b, 94, 100);  // header size below 375 for 1.4
  expect_error(b, "header size");
  b = good;
  put<double>(b, 131, 0.0);  // zero scale
  expect_error(b, "scale");
  b = good;
  put<std::uint8_t>(b, 104, 11);  // unknown format
  expect_error(b, "format");
  b = good;
  b.resize(b.size() - 1);  // truncated last record
  expect_error(b, "truncated");
}

TEST(Las, RealForestPlotHeaderAndPoints) {
  FIELDLIDAR_REQUIRE_DATA("forest_tls/pine_plot.las");
  const auto path = test::data_file("forest_tls/pine_plot.las");
  const auto h = io::read_las_header(path);
  EXPECT_EQ(h.version_major, 1);
  EXPECT_EQ(h.version_minor, 2);
  EXPECT_EQ(h.point_format, 0);
  EXPECT_EQ(h.point_count, 114024u);
  EXPECT_DOUBLE_EQ(h.scale.x(), 1e-4);
  EXPECT_NEAR(h.offset.z(), 49.0254, 1e-9);
  const auto las = io::read_las(path);
  EXPECT_EQ(las.cloud.size(), 114024u);
  EXPECT_EQ(las.origin_m, Eigen::Vector3d::Zero());  // a 10 m plot keeps its own coordinates
  const auto b = compute_bounds(las.cloud);
  // The points lie inside the header's bounds (to the 0.1 mm scale and float rounding).
  for (int a = 0; a < 3; ++a) {
    EXPECT_GE(b.min[a], h.min[a] - 1e-3);
    EXPECT_LE(b.max[a], h.max[a] + 1e-3);
    EXPECT_LT(b.min[a], h.min[a] + 0.05);
    EXPECT_GT(b.max[a], h.max[a] - 0.05);
  }
}

TEST(Las, RealForestSingleTreesAndStemSlice) {
  struct Expect {
    const char* file;
    std::uint64_t count;
    int minor;
  };
  for (const Expect& e :
       {Expect{"forest_tls/pine.las", 73851, 2}, Expect{"forest_tls/spruce.las", 83392, 2},
        Expect{"forest_tls/dbh.las", 1369, 4}}) {
    SCOPED_TRACE(e.file);
    if (!std::filesystem::exists(test::data_file(e.file))) GTEST_SKIP() << e.file << " absent";
    const auto las = io::read_las(test::data_file(e.file));
    EXPECT_EQ(las.header.version_minor, e.minor);
    EXPECT_EQ(las.cloud.size(), e.count);
    EXPECT_EQ(las.header.point_count, e.count);
    EXPECT_EQ(las.cloud.valid_count(), e.count);
  }
}

TEST(Las, RealTerrainHasItsGroundClassAndLocalOrigin) {
  FIELDLIDAR_REQUIRE_DATA("terrain_als/Topography.las");
  const auto las = io::read_las(test::data_file("terrain_als/Topography.las"));
  EXPECT_EQ(las.header.point_count, 73403u);
  EXPECT_EQ(las.header.point_format, 1);
  EXPECT_DOUBLE_EQ(las.header.scale.x(), 0.00025);
  EXPECT_DOUBLE_EQ(las.header.offset.x(), 270000.0);
  EXPECT_DOUBLE_EQ(las.header.offset.y(), 5270000.0);
  ASSERT_EQ(las.cloud.size(), 73403u);
  // UTM coordinates are shifted by a whole-km origin so float32 keeps sub-mm resolution.
  EXPECT_EQ(las.origin_m, Eigen::Vector3d(273000, 5274000, 0));
  const auto b = compute_bounds(las.cloud);
  EXPECT_NEAR(b.min.x() + las.origin_m.x(), las.header.min.x(), 1e-3);
  EXPECT_NEAR(b.max.y() + las.origin_m.y(), las.header.max.y(), 1e-3);
  EXPECT_NEAR(b.max.z() - b.min.z(), 40.765, 0.01);  // ~41 m of relief
  // Classification as decoded independently of this reader: 8159 ground (2), 3897 water (9),
  // the rest unclassified (1).
  const auto count = [&](std::uint32_t c) {
    return std::count(las.cloud.labels.begin(), las.cloud.labels.end(), c);
  };
  EXPECT_EQ(count(2), 8159);
  EXPECT_EQ(count(9), 3897);
  EXPECT_EQ(count(1), 61347);
  const double ground_fraction = double(count(2)) / las.cloud.size();
  EXPECT_GT(ground_fraction, 0.05);
  EXPECT_LT(ground_fraction, 0.2);
  // GPS time: one flight strip of a few seconds.
  EXPECT_GT(las.cloud.stamp_s, 1e8);
  const auto tmax =
      std::max_element(las.cloud.points.begin(), las.cloud.points.end(),
                       [](const Point& a, const Point& b) { return a.time < b.time; });
  EXPECT_GT(tmax->time, 1.0f);
  EXPECT_LT(tmax->time, 60.0f);
}
