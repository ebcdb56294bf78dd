// fieldlidar convert keeps a LAS file's georeference in PCD and PLY and says so; KITTI .bin,
// which cannot hold it, gets a warning.

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "fieldlidar/io/cloud_file.hpp"
#include "run_cli.hpp"
#include "test_data.hpp"

namespace fieldlidar {
namespace {

TEST(CliConvertGeoreference, LasOriginKeptAndReported) {
  const std::string name = "terrain_als/Topography.las";
  FIELDLIDAR_REQUIRE_DATA(name);
  const auto las = test::quoted(test::data_file(name));
  const auto dir = test::temp_dir("convert_georeference");
  for (const char* file : {"topo.pcd", "topo.ply"}) {
    const auto r = test::run_cli("convert " + las + " " + test::quoted(dir / file));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("kept the georeference"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("273000.000, 5274000.000, 0.000"), std::string::npos) << r.output;
    EXPECT_EQ(io::read_cloud(dir / file).origin_m, Eigen::Vector3d(273000, 5274000, 0)) << file;
    const auto info = test::run_cli("info " + test::quoted(dir / file));
    EXPECT_NE(info.output.find("origin:  (273000.000, 5274000.000, 0.000) m"), std::string::npos)
        << info.output;
  }
  const auto bin = test::run_cli("convert " + las + " " + test::quoted(dir / "topo.bin"));
  EXPECT_EQ(bin.exit_code, 0) << bin.output;
  EXPECT_NE(bin.output.find("fieldlidar: warning: KITTI .bin has no place for the georeference"),
            std::string::npos)
      << bin.output;
}

}  // namespace
}  // namespace fieldlidar
