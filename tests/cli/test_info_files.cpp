// `fieldlidar info --json` on every real file of ../shared/data, and `convert` round trips.
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "fieldlidar/io/cloud_file.hpp"
#include "fieldlidar/io/las.hpp"
#include "run_cli.hpp"
#include "test_data.hpp"

using namespace fieldlidar;
namespace fs = std::filesystem;

namespace {

nlohmann::json info_json(const fs::path& file) {
  const auto r = test::run_cli("info --json '" + file.string() + "'");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  try {
    return nlohmann::json::parse(r.output);
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not JSON: " << r.output;
    return {};
  }
}

}  // namespace

TEST(InfoFiles, KittiAndRellisScans) {
  FIELDLIDAR_REQUIRE_DATA("kitti00/000000.bin");
  const auto j = info_json(test::data_file("kitti00/000000.bin"));
  EXPECT_EQ(j.value("format", ""), "kitti-bin");
  EXPECT_EQ(j.value("frames", 0), 1);
  EXPECT_EQ(j.value("points", 0), 124668);
  // Every KITTI frame: 16 bytes per point.
  for (int i = 1; i <= 5; ++i) {
    const auto file = test::data_file("kitti00/00000" + std::to_string(i) + ".bin");
    EXPECT_EQ(info_json(file).value("points", std::size_t{0}), fs::file_size(file) / 16) << file;
  }
  FIELDLIDAR_REQUIRE_DATA("rellis3d/000001.bin");
  EXPECT_EQ(info_json(test::data_file("rellis3d/000001.bin")).value("points", 0), 131072);
}

TEST(InfoFiles, Ouster128Pcd) {
  FIELDLIDAR_REQUIRE_DATA("pcd_os128/000000.pcd");
  const auto j = info_json(test::data_file("pcd_os128/000000.pcd"));
  EXPECT_EQ(j.value("format", ""), "pcd");
  EXPECT_EQ(j.value("points", 0), 240000);  // header: WIDTH 1875 x HEIGHT 128
  EXPECT_EQ(j.value("rings", 0), 128);
  ASSERT_TRUE(j.contains("organized"));
  EXPECT_EQ(j["organized"].value("width", 0), 1875);
  EXPECT_EQ(j["organized"].value("height", 0), 128);
}

TEST(InfoFiles, LasFilesReportTheirHeaderCounts) {
  struct Expect {
    const char* file;
    int points;
  };
  // Counts as stored in each file's public header block (legacy or LAS 1.4 64-bit count).
  for (const Expect& e :
       {Expect{"forest_tls/pine_plot.las", 114024}, Expect{"forest_tls/pine.las", 73851},
        Expect{"forest_tls/spruce.las", 83392}, Expect{"forest_tls/dbh.las", 1369},
        Expect{"terrain_als/Topography.las", 73403}}) {
    SCOPED_TRACE(e.file);
    const auto path = test::data_file(e.file);
    if (!fs::exists(path)) GTEST_SKIP() << path << " absent";
    const auto j = info_json(path);
    EXPECT_EQ(j.value("format", ""), "las");
    EXPECT_EQ(j.value("points", 0), e.points);
    EXPECT_EQ(io::read_las_header(path).point_count, static_cast<std::uint64_t>(e.points));
  }
}

TEST(InfoFiles, ConvertRoundTripBinPcdPlyBin) {
  FIELDLIDAR_REQUIRE_DATA("kitti00/000000.bin");
  const auto dir = test::temp_dir("cli_convert_chain");
  const auto src = test::data_file("kitti00/000000.bin");
  auto convert = [](const fs::path& in, const fs::path& out, const std::string& flags = "") {
    return test::run_cli("convert " + flags + " '" + in.string() + "' '" + out.string() + "'");
  };
  ASSERT_EQ(convert(src, dir / "a.pcd", "--compressed").exit_code, 0);
  ASSERT_EQ(convert(dir / "a.pcd", dir / "b.ply").exit_code, 0);
  ASSERT_EQ(convert(dir / "b.ply", dir / "c.bin").exit_code, 0);
  const auto original = io::read_cloud(src);
  const auto back = io::read_cloud(dir / "c.bin");
  ASSERT_EQ(back.size(), original.size());
  std::size_t differing = 0;
  for (std::size_t i = 0; i < back.size(); ++i) {
    const auto& a = original.points[i];
    const auto& b = back.points[i];
    differing += a.x != b.x || a.y != b.y || a.z != b.z || a.intensity != b.intensity;
  }
  EXPECT_EQ(differing, 0u);
  EXPECT_EQ(fs::file_size(dir / "c.bin"), fs::file_size(src));
  // ascii PCD too
  ASSERT_EQ(convert(src, dir / "d.pcd", "--ascii").exit_code, 0);
  EXPECT_EQ(io::read_cloud(dir / "d.pcd").size(), original.size());
}

TEST(InfoFiles, ConvertRefusesToOverwriteWithoutForce) {
  FIELDLIDAR_REQUIRE_DATA("kitti00/000000.bin");
  const auto dir = test::temp_dir("cli_convert_force");
  const auto src = test::data_file("kitti00/000000.bin");
  { std::ofstream(dir / "keep.pcd") << "precious"; }
  const auto r =
      test::run_cli("convert '" + src.string() + "' '" + (dir / "keep.pcd").string() + "'");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("already exists"), std::string::npos) << r.output;
  std::ifstream in(dir / "keep.pcd");
  std::string kept;
  in >> kept;
  EXPECT_EQ(kept, "precious");
  const auto forced =
      test::run_cli("convert --force '" + src.string() + "' '" + (dir / "keep.pcd").string() + "'");
  EXPECT_EQ(forced.exit_code, 0) << forced.output;
  EXPECT_EQ(io::read_cloud(dir / "keep.pcd").size(), 124668u);
}

TEST(InfoFiles, LazAndBrokenFilesFailWithTheFileNamed) {
  const auto dir = test::temp_dir("cli_info_errors");
  {
    std::ofstream(dir / "scan.laz") << "LASF";
    std::ofstream(dir / "bad.pcd") << "not a point cloud\n";
  }
  auto r = test::run_cli("info '" + (dir / "scan.laz").string() + "'");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("compressed LAZ is not supported, decompress it first"),
            std::string::npos)
      << r.output;
  r = test::run_cli("info --json '" + (dir / "bad.pcd").string() + "'");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("bad.pcd"), std::string::npos) << r.output;
}
