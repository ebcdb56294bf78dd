// PointCloud::origin_m (a LAS file's projected origin) survives PCD and PLY round trips, so that
// a converted LAS cloud keeps its absolute coordinates while its points stay small float32s.

#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "fieldlidar/io/cloud_file.hpp"
#include "fieldlidar/io/las.hpp"
#include "test_data.hpp"

namespace fieldlidar {
namespace {

namespace fs = std::filesystem;

PointCloud small_cloud(const Eigen::Vector3d& origin) {
  PointCloud c;
  c.fields.intensity = true;
  c.push_back({357.145f, 642.847f, 788.993f, 12.f});
  c.push_back({642.857f, 357.143f, 829.758f, 40.f});
  c.origin_m = origin;
  return c;
}

std::string header_of(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::string text(2048, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  text.resize(static_cast<std::size_t>(in.gcount()));
  return text.substr(0, text.find("DATA"));
}

TEST(Georeference, OriginSurvivesEveryPcdAndPlyEncoding) {
  const auto dir = test::temp_dir("georeference");
  // A PCD keeps any origin exactly; PLY (float32 viewpoint) keeps whole metres, as LAS origins are.
  const Eigen::Vector3d origin(273000.0, 5274000.0, 125.0);
  const PointCloud cloud = small_cloud(origin);
  struct Case {
    const char* file;
    io::WriteOptions options;
  };
  for (const auto& c :
       {Case{"b.pcd", {}}, Case{"a.pcd", {.binary = false}}, Case{"c.pcd", {.compressed = true}},
        Case{"b.ply", {}}, Case{"a.ply", {.binary = false}}}) {
    io::write_cloud(dir / c.file, cloud, c.options);
    const PointCloud back = io::read_cloud(dir / c.file);
    EXPECT_EQ(back.origin_m, origin) << c.file;
    ASSERT_EQ(back.size(), cloud.size()) << c.file;
    EXPECT_EQ(back.points[1].x, cloud.points[1].x) << c.file;
  }
  EXPECT_NE(header_of(dir / "b.pcd").find("VIEWPOINT 273000 5274000 125 1 0 0 0"),
            std::string::npos)
      << header_of(dir / "b.pcd");
  // A PCD origin is not limited to float32.
  PointCloud fine = small_cloud({273000.125, 5274000.375, 0.001});
  io::write_cloud(dir / "fine.pcd", fine);
  EXPECT_EQ(io::read_cloud(dir / "fine.pcd").origin_m, fine.origin_m);
  // Sensor clouds keep the plain header.
  io::write_cloud(dir / "plain.pcd", small_cloud(Eigen::Vector3d::Zero()));
  EXPECT_NE(header_of(dir / "plain.pcd").find("VIEWPOINT 0 0 0 1 0 0 0"), std::string::npos);
  EXPECT_TRUE(io::read_cloud(dir / "plain.pcd").origin_m.isZero());
}

TEST(Georeference, RotatedViewpointIsNotAnOrigin) {
  const auto dir = test::temp_dir("georeference_rotated");
  std::ofstream(dir / "r.pcd")
      << "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
         "WIDTH 1\nHEIGHT 1\nVIEWPOINT 5 6 7 0 0 0 1\nPOINTS 1\nDATA ascii\n"
         "1 2 3\n";
  EXPECT_TRUE(io::read_cloud(dir / "r.pcd").origin_m.isZero());
}

TEST(Georeference, LasOffsetKeptThroughPcdAndPly) {
  const std::string name = "terrain_als/Topography.las";
  FIELDLIDAR_REQUIRE_DATA(name);
  const auto las = io::read_las(test::data_file(name));
  EXPECT_EQ(las.cloud.origin_m, Eigen::Vector3d(273000, 5274000, 0));
  const auto dir = test::temp_dir("georeference_las");
  for (const char* file : {"topo.pcd", "topo.ply"}) {
    io::write_cloud(dir / file, las.cloud);
    const PointCloud back = io::read_cloud(dir / file);
    ASSERT_EQ(back.size(), las.cloud.size());
    EXPECT_EQ(back.origin_m, las.cloud.origin_m) << file;
    // Absolute coordinates of the last point, as in the LAS file (float32 local part: < 0.1 mm).
    const Eigen::Vector3d abs_las =
        las.cloud.origin_m + las.cloud.points.back().xyz().cast<double>();
    const Eigen::Vector3d abs_back = back.origin_m + back.points.back().xyz().cast<double>();
    EXPECT_LT((abs_las - abs_back).norm(), 1e-4) << file;
    EXPECT_GT(abs_back.y(), 5274000.0) << file;
  }
}

}  // namespace
}  // namespace fieldlidar
