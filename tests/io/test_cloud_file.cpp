#include <fstream>

#include <gtest/gtest.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/cloud_file.hpp"
#include "test_data.hpp"

using namespace fieldlidar;

TEST(CloudFile, FormatByExtension) {
  EXPECT_EQ(io::cloud_format_of("a/b.PCD"), io::CloudFormat::kPcd);
  EXPECT_EQ(io::cloud_format_of("x.ply"), io::CloudFormat::kPly);
  EXPECT_EQ(io::cloud_format_of("x.las"), io::CloudFormat::kLas);
  EXPECT_EQ(io::cloud_format_of("x.laz"), io::CloudFormat::kLas);
  EXPECT_EQ(io::cloud_format_of("x.bin"), io::CloudFormat::kKittiBin);
  EXPECT_FALSE(io::cloud_format_of("x.txt"));
}

TEST(CloudFile, KittiThroughPcdAndPlyBackToBinKeepsEveryPoint) {
  FIELDLIDAR_REQUIRE_DATA("kitti00/000000.bin");
  const auto src = io::read_cloud(test::data_file("kitti00/000000.bin"));
  const auto dir = test::temp_dir("cloud_chain");
  io::write_cloud(dir / "a.pcd", src, {.compressed = true});
  io::write_cloud(dir / "b.ply", io::read_cloud(dir / "a.pcd"));
  io::write_cloud(dir / "c.bin", io::read_cloud(dir / "b.ply"));
  const auto back = io::read_cloud(dir / "c.bin");
  ASSERT_EQ(back.size(), 124668u);
  for (std::size_t i = 0; i < back.size(); ++i) {
    ASSERT_EQ(back.points[i].x, src.points[i].x) << i;
    ASSERT_EQ(back.points[i].y, src.points[i].y) << i;
    ASSERT_EQ(back.points[i].z, src.points[i].z) << i;
    ASSERT_EQ(back.points[i].intensity, src.points[i].intensity) << i;
  }
}

TEST(CloudFile, ClearErrorsForLazLasOutputAndUnknownTypes) {
  const auto dir = test::temp_dir("cloud_errors");
  std::ofstream(dir / "x.laz") << "LASF";
  try {
    io::read_cloud(dir / "x.laz");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("compressed LAZ is not supported, decompress it first"),
              std::string::npos);
  }
  PointCloud c;
  c.push_back({1, 2, 3});
  EXPECT_THROW(io::write_cloud(dir / "o.las", c), Error);
  EXPECT_THROW(io::write_cloud(dir / "o.xyz", c), Error);
  EXPECT_THROW(io::read_cloud(dir / "missing.pcd"), Error);
}
