// fieldlidar simulate writes one PCD schema for every frame of a folder (time = s from the sweep
// start, as documented), frame 0 (stamp 0 s) included.

#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "fieldlidar/io/cloud_file.hpp"
#include "run_cli.hpp"
#include "test_data.hpp"

namespace fieldlidar {
namespace {

namespace fs = std::filesystem;

std::string fields_line(const fs::path& pcd) {
  std::ifstream in(pcd, std::ios::binary);
  for (std::string line; std::getline(in, line);)
    if (line.rfind("FIELDS ", 0) == 0) return line;
  return {};
}

TEST(CliSimulateSchema, EveryPcdFrameHasTheSameFields) {
  const auto dir = test::temp_dir("simulate_schema");
  const auto r =
      test::run_cli("simulate --scene forest --sensor vlp16 --frames 3 --out " + test::quoted(dir));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (int i = 0; i < 3; ++i) {
    const auto pcd = dir / "pcd" / ("00000" + std::to_string(i) + ".pcd");
    EXPECT_EQ(fields_line(pcd), "FIELDS x y z intensity ring time label") << pcd;
    const PointCloud c = io::read_cloud(pcd);
    ASSERT_GT(c.size(), 1000u);
    EXPECT_TRUE(c.fields.time);
    EXPECT_EQ(c.stamp_s, 0.0);  // offsets only; the sweep stamps are in times.txt
    float t_max = 0.f;
    for (const auto& p : c.points) t_max = std::max(t_max, p.time);
    EXPECT_GT(t_max, 0.09f);  // a VLP-16 sweep lasts 0.1 s
    EXPECT_LT(t_max, 0.1001f);
  }
}

}  // namespace
}  // namespace fieldlidar
