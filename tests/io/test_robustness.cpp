// Every reader meets empty, truncated, wrong-magic and NaN-filled input and answers with a
// fieldlidar::Error that names the file: no crash, no hang, no other exception type.
#include <cstring>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/cloud_file.hpp"
#include "fieldlidar/io/file_util.hpp"
#include "fieldlidar/io/label_file.hpp"
#include "fieldlidar/io/las.hpp"
#include "fieldlidar/io/pcd.hpp"
#include "fieldlidar/io/ply.hpp"
#include "fieldlidar/io/trajectory_io.hpp"
#include "test_data.hpp"

using namespace fieldlidar;

namespace {

PointCloud small_cloud(int n = 12) {
  PointCloud c;
  c.fields = {.intensity = true, .ring = true, .time = true};
  for (int i = 0; i < n; ++i) {
    Point p{0.5f * i, 1.f - 0.25f * i, 0.1f * i, float(i)};
    p.ring = static_cast<std::uint16_t>(i % 4);
    p.time = 0.001f * i;
    c.push_back(p);
  }
  return c;
}

std::vector<std::byte> bytes_of(const std::filesystem::path& p) {
  return io::read_file_bytes(p);
}

void write_bytes(const std::filesystem::path& p, std::span<const std::byte> b) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
}

/// Runs `read`, which must throw fieldlidar::Error whose message contains `name`.
template <typename Read>
void expect_error_naming(Read read, const std::string& name, const std::string& what) {
  SCOPED_TRACE(what);
  try {
    read();
    ADD_FAILURE() << "accepted " << what;
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "wrong exception type for " << what << ": " << e.what();
  }
}

std::vector<std::byte> text_bytes(const std::string& s) {
  std::vector<std::byte> b(s.size());
  std::memcpy(b.data(), s.data(), s.size());
  return b;
}

}  // namespace

TEST(Robustness, EmptyFilesAreErrorsForStructuredFormats) {
  const auto dir = test::temp_dir("robust_empty");
  for (const char* name : {"e.pcd", "e.ply", "e.las"}) {
    write_bytes(dir / name, {});
    expect_error_naming([&] { io::read_cloud(dir / name); }, name, name);
  }
  expect_error_naming([&] { io::read_las_header(dir / "e.las"); }, "e.las", "empty LAS header");
  // Formats without a header: an empty file is a valid empty scan / trajectory.
  write_bytes(dir / "e.bin", {});
  EXPECT_TRUE(io::read_cloud(dir / "e.bin").empty());
  write_bytes(dir / "e.label", {});
  EXPECT_TRUE(io::read_labels(dir / "e.label").empty());
  write_bytes(dir / "e.txt", {});
  EXPECT_TRUE(io::read_tum(dir / "e.txt").empty());
}

TEST(Robustness, EveryTruncationOfABinaryPcdIsAnError) {
  const auto dir = test::temp_dir("robust_pcd_trunc");
  for (bool compressed : {false, true}) {
    io::write_pcd(dir / "full.pcd", small_cloud(), {.overwrite = true, .compressed = compressed});
    const auto full = bytes_of(dir / "full.pcd");
    ASSERT_NO_THROW(io::parse_pcd(full, "full.pcd"));
    for (std::size_t len = 0; len < full.size(); ++len)
      expect_error_naming(
          [&] { io::parse_pcd(std::span(full).first(len), "cut.pcd"); }, "cut.pcd",
          (compressed ? "compressed PCD cut at " : "binary PCD cut at ") + std::to_string(len));
  }
}

TEST(Robustness, PcdHeaderNumbersThatWouldOverflowAreErrors) {
  // WIDTH x HEIGHT x point size wraps around 2^64 to a small number: must not pass the size check.
  for (const char* data : {"binary", "binary_compressed", "ascii"}) {
    const std::string text =
        std::string(
            "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 4294967295\n"
            "HEIGHT 4294967295\nPOINTS 18446744065119617025\nDATA ") +
        data + "\n" + std::string(64, '\x01');
    expect_error_naming([&] { io::parse_pcd(text_bytes(text), "huge.pcd"); }, "huge.pcd", data);
  }
  const std::string step =
      "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 4611686018427387904\n"
      "WIDTH 1\nPOINTS 1\nDATA binary\n" +
      std::string(64, '\x01');
  expect_error_naming([&] { io::parse_pcd(text_bytes(step), "count.pcd"); }, "count.pcd", "COUNT");
  // A SIZE past 8 bytes is named with the value given, not a clamped one.
  const std::string size =
      "FIELDS x y z\nSIZE 4611686018427387904 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
      "WIDTH 1\nPOINTS 1\nDATA binary\n" +
      std::string(64, '\x01');
  expect_error_naming([&] { io::parse_pcd(text_bytes(size), "size.pcd"); }, "size.pcd",
                      "field 'x' has SIZE 4611686018427387904 (1, 2, 4 or 8 bytes)");
}

TEST(Robustness, TruncatedAsciiPcdNeverReturnsFewerPoints) {
  const auto dir = test::temp_dir("robust_pcd_ascii");
  const auto cloud = small_cloud();
  io::write_pcd(dir / "a.pcd", cloud, {.binary = false});
  const auto full = bytes_of(dir / "a.pcd");
  for (std::size_t len = 0; len < full.size(); ++len) {
    // A cut inside the last number cannot be told from a shorter number; a cut anywhere else is
    // an error, and no cut ever yields a cloud with a different point count.
    try {
      const auto c = io::parse_pcd(std::span(full).first(len), "cut.pcd");
      EXPECT_EQ(c.size(), cloud.size()) << len;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("cut.pcd"), std::string::npos);
    }
  }
}

TEST(Robustness, EveryTruncationOfALasIsAnError) {
  FIELDLIDAR_REQUIRE_DATA("forest_tls/dbh.las");
  // dbh.las is LAS 1.4 with a VLR; cutting it anywhere must be caught.
  const auto full = bytes_of(test::data_file("forest_tls/dbh.las"));
  ASSERT_NO_THROW(io::parse_las(full, "dbh.las"));
  for (std::size_t len = 0; len < full.size(); len += (len < 1300 ? 1 : 97))
    expect_error_naming([&] { io::parse_las(std::span(full).first(len), "cut.las"); }, "cut.las",
                        "LAS cut at " + std::to_string(len));
}

TEST(Robustness, TruncatedPlyIsAnError) {
  const auto dir = test::temp_dir("robust_ply");
  io::write_ply(dir / "full.ply", small_cloud());
  const auto full = bytes_of(dir / "full.ply");
  for (std::size_t len = 0; len < full.size(); len += 7) {
    write_bytes(dir / "cut.ply", std::span(full).first(len));
    expect_error_naming([&] { io::read_ply(dir / "cut.ply"); }, "cut.ply",
                        "PLY cut at " + std::to_string(len));
  }
}

TEST(Robustness, PlyOrganizedSizeMustMatchTheVertexCount) {
  // PCL aborts the process when obj_info num_cols x num_rows does not fit the vertex list (found
  // by fuzzing); the reader must refuse such a header before PCL sees it.
  const auto dir = test::temp_dir("robust_ply_objinfo");
  const std::string body =
      "element vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nend_header\n0 0 1\n1 0 1\n2 0 1\n";
  for (const std::string& info :
       {std::string("obj_info num_cols 2\nobj_info num_rows 1\n"),
        std::string("obj_info num_cols 3\n"),
        std::string("obj_info num_cols 3x\nobj_info num_rows 1\n"),
        std::string("obj_info num_cols 4294967296\nobj_info num_rows 4294967296\n")}) {
    write_bytes(dir / "bad.ply", text_bytes("ply\nformat ascii 1.0\n" + info + body));
    expect_error_naming([&] { io::read_ply(dir / "bad.ply"); }, "bad.ply", info);
  }
  // PCL's parser asserts on an obj_info line with leading white space (found by fuzzing).
  write_bytes(dir / "space.ply", text_bytes("ply\nformat ascii 1.0\n obj_info is_mesh 0\n" + body));
  expect_error_naming([&] { io::read_ply(dir / "space.ply"); }, "space.ply", "leading space");
  write_bytes(dir / "good.ply", text_bytes("ply\nformat ascii 1.0\nobj_info num_cols 3\n"
                                           "obj_info num_rows 1\n" +
                                           body));
  EXPECT_EQ(io::read_ply(dir / "good.ply").size(), 3u);
}

TEST(Robustness, WrongMagicIsAnError) {
  const auto dir = test::temp_dir("robust_magic");
  const auto junk = text_bytes("GIF89a this is a picture, not a point cloud\n\x01\x02\x03");
  for (const char* name : {"j.pcd", "j.ply", "j.las"}) {
    write_bytes(dir / name, junk);
    expect_error_naming([&] { io::read_cloud(dir / name); }, name, name);
  }
  // A PLY body behind a PCD extension, and a PCD behind a LAS one.
  io::write_ply(dir / "p.ply", small_cloud());
  std::filesystem::copy_file(dir / "p.ply", dir / "p.pcd");
  expect_error_naming([&] { io::read_cloud(dir / "p.pcd"); }, "p.pcd", "PLY as PCD");
  io::write_pcd(dir / "q.pcd", small_cloud());
  std::filesystem::copy_file(dir / "q.pcd", dir / "q.las");
  expect_error_naming([&] { io::read_cloud(dir / "q.las"); }, "q.las", "PCD as LAS");
  expect_error_naming([&] { io::parse_tum("GIF89a\n", "j.tum"); }, "j.tum", "TUM junk");
  expect_error_naming([&] { io::parse_kitti_poses("\x89PNG\r\n", "j.txt"); }, "j.txt",
                      "KITTI junk");
}

TEST(Robustness, NanFilledInputIsAnError) {
  const auto dir = test::temp_dir("robust_nan");
  PointCloud nan_cloud;
  for (int i = 0; i < 10; ++i) {
    const float q = std::numeric_limits<float>::quiet_NaN();
    nan_cloud.push_back({q, q, q, q});
  }
  for (const char* name : {"n.pcd", "n.ply", "n.bin"}) {
    io::write_cloud(dir / name, nan_cloud);
    expect_error_naming([&] { io::read_cloud(dir / name); }, name, name);
  }
  // Organized PCD of nothing but no-returns: also refused rather than returned as all zeros.
  nan_cloud.width = 5;
  nan_cloud.height = 2;
  io::write_pcd(dir / "org.pcd", nan_cloud, {.compressed = true});
  expect_error_naming([&] { io::read_pcd(dir / "org.pcd"); }, "org.pcd", "organized all-NaN");
  // LAS stores integers, but its GPS time and header scale are doubles.
  FIELDLIDAR_REQUIRE_DATA("terrain_als/Topography.las");
  auto las = bytes_of(test::data_file("terrain_als/Topography.las"));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto bad_time = las;
  std::uint32_t offset;
  std::memcpy(&offset, las.data() + 96, 4);
  std::memcpy(bad_time.data() + offset + 20, &nan, 8);
  expect_error_naming([&] { io::parse_las(bad_time, "t.las"); }, "t.las", "NaN GPS time");
  auto bad_scale = las;
  std::memcpy(bad_scale.data() + 139, &nan, 8);
  expect_error_naming([&] { io::parse_las(bad_scale, "s.las"); }, "s.las", "NaN scale");
  expect_error_naming([&] { io::parse_tum("0 nan 0 0 0 0 0 1\n", "n.tum"); }, "n.tum", "NaN TUM");
  expect_error_naming([&] { io::parse_kitti_times("0\nnan\n", "n.times"); }, "n.times", "NaN time");
}
