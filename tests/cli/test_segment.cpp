// End-to-end: fieldlidar segment and eval-ground on real frames.

#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "run_cli.hpp"
#include "test_data.hpp"

namespace fieldlidar::test {
namespace {

// Joins the words with spaces (a stream: GCC 12's -Wrestrict misfires on chains of operator+).
std::string args(std::initializer_list<std::string> words) {
  std::ostringstream s;
  for (const auto& w : words) s << w << ' ';
  return s.str();
}

TEST(CliSegment, WritesLabelsCloudAndPicturesAndRefusesToOverwrite) {
  FIELDLIDAR_REQUIRE_DATA("kitti00/000000.bin");
  const auto dir = temp_dir("cli_segment");
  const auto in = data_file("kitti00/000000.bin");
  const auto labels = dir / "out.label", png = dir / "out.png", pcd = dir / "out.pcd";
  const auto r =
      run_cli(args({"segment", quoted(in), "--sensor", "hdl64e", "--labels", quoted(labels),
                    "--png", quoted(png), "--out", quoted(pcd), "--json"}));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output);
  EXPECT_EQ(j["points"].get<long>(), 124668);
  EXPECT_GT(j["clusters"].get<long>(), 50);
  EXPECT_NEAR(j["sensor_height_m"].get<double>(), 1.73, 0.1);  // KITTI's HDL-64E mount
  ASSERT_EQ(std::filesystem::file_size(labels), 124668u * 4);
  std::ifstream f(labels, std::ios::binary);
  std::vector<std::uint32_t> l(124668);
  f.read(reinterpret_cast<char*>(l.data()), std::streamsize(l.size() * 4));
  std::size_t ground = 0, clustered = 0, other = 0, bad = 0;
  for (auto v : l) {
    if (v == 1)
      ++ground;
    else if (v == 2)
      ++other;
    else if (v >= 100)
      ++clustered;
    else
      ++bad;
  }
  EXPECT_EQ(bad, 0u);  // every KITTI point is a valid return
  EXPECT_EQ(long(ground), j["ground_points"].get<long>());
  EXPECT_GT(clustered, 30000u);
  EXPECT_GT(std::filesystem::file_size(png), 10000u);
  EXPECT_TRUE(std::filesystem::exists(dir / "out.range.png"));
  EXPECT_TRUE(std::filesystem::exists(pcd));
  // Outputs exist now: without --force nothing is replaced.
  const auto again = run_cli(args({"segment", quoted(in), "--labels", quoted(labels)}));
  EXPECT_EQ(again.exit_code, 1);
  EXPECT_NE(again.output.find("fieldlidar: error:"), std::string::npos);
  EXPECT_EQ(run_cli(args({"segment", quoted(in), "--labels", quoted(labels), "--force"})).exit_code,
            0);
  EXPECT_EQ(run_cli(args({"segment", quoted(in), "--method", "nonsense"})).exit_code, 1);
  EXPECT_EQ(run_cli(args({"segment", quoted(dir / "missing.bin")})).exit_code, 1);
}

TEST(CliSegment, SaysWhatItGuessesAndTakesTheGridGroundForASurvey) {
  FIELDLIDAR_REQUIRE_DATA("terrain_als/Topography.las");
  FIELDLIDAR_REQUIRE_DATA("kitti00/000000.bin");
  // No ring field and no --sensor: the sensor is a guess, and said to be one.
  const auto kitti = run_cli(args({"segment", quoted(data_file("kitti00/000000.bin"))}));
  ASSERT_EQ(kitti.exit_code, 0) << kitti.output;
  EXPECT_NE(kitti.output.find("warning: "), std::string::npos) << kitti.output;
  EXPECT_NE(kitti.output.find("sensor assumed hdl64e (give --sensor)"), std::string::npos);
  EXPECT_NE(kitti.output.find("(robust)"), std::string::npos) << kitti.output;
  // An airborne LAS tile is no sweep: the grid ground, with a warning saying why (it found 0
  // ground returns of 8,159 classified ones as an HDL-64E sweep).
  const auto las =
      run_cli(args({"segment", quoted(data_file("terrain_als/Topography.las")), "--json"}));
  ASSERT_EQ(las.exit_code, 0) << las.output;
  EXPECT_NE(las.output.find("warning: "), std::string::npos) << las.output;
  EXPECT_NE(las.output.find("not one sensor sweep"), std::string::npos) << las.output;
  const auto j = nlohmann::json::parse(las.output.substr(las.output.find('{')));
  EXPECT_EQ(j["method"].get<std::string>(), "grid");
  EXPECT_TRUE(j["sensor"].is_null());
  EXPECT_GT(j["ground_points"].get<long>(), 12000);
  EXPECT_LT(j["ground_points"].get<long>(), 25000);
  // A tilted sensor: --up levels the cloud first; a zero direction is refused.
  const auto up = run_cli(args({"segment", quoted(data_file("kitti00/000000.bin")), "--sensor",
                                "hdl64e", "--up", "0.5,0,1", "--json"}));
  ASSERT_EQ(up.exit_code, 0) << up.output;
  const auto ju = nlohmann::json::parse(up.output);
  EXPECT_NEAR(ju["tilt_deg"].get<double>(), 26.57, 0.01);
  EXPECT_TRUE(ju["levelled"].get<bool>());
  EXPECT_EQ(run_cli(args({"segment", quoted(data_file("kitti00/000000.bin")), "--up", "0,0,0"}))
                .exit_code,
            1);
  // Options that need a sweep are refused on a survey rather than ignored.
  const auto topo = quoted(data_file("terrain_als/Topography.las"));
  EXPECT_EQ(run_cli(args({"segment", topo, "--up", "0,0,1"})).exit_code, 1);
  EXPECT_EQ(run_cli(args({"segment", topo, "--clusters", "range-image"})).exit_code, 1);
}

TEST(CliEvalGround, ScoresRellisLikeTheLibrary) {
  FIELDLIDAR_REQUIRE_DATA("rellis3d/000001.label");
  const auto r = run_cli(args({"eval-ground", quoted(data_file("rellis3d/000001.bin")),
                               quoted(data_file("rellis3d/000001.label")), "--classes", "rellis",
                               "--sensor", "os1-64", "--json"}));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output);
  EXPECT_GE(j["f1"].get<double>(), 0.96);
  EXPECT_GT(j["precision"].get<double>(), 0.9);
  EXPECT_GT(j["recall"].get<double>(), 0.9);
  const long scored = j["true_positive"].get<long>() + j["false_positive"].get<long>() +
                      j["false_negative"].get<long>() + j["true_negative"].get<long>();
  EXPECT_EQ(scored, 61781);  // valid returns that are not void
  const auto s002 = run_cli(args({"eval-ground", quoted(data_file("rellis3d/000001.bin")),
                                  quoted(data_file("rellis3d/000001.label")), "--classes", "rellis",
                                  "--sensor", "os1-64", "--method", "seed002", "--json"}));
  ASSERT_EQ(s002.exit_code, 0) << s002.output;
  EXPECT_GT(nlohmann::json::parse(s002.output)["precision"].get<double>(), 0.99);
  EXPECT_EQ(run_cli(args({"eval-ground", quoted(data_file("rellis3d/000001.bin")),
                          quoted(data_file("kitti00/000000.bin")), "--classes", "rellis"}))
                .exit_code,
            1);  // label count does not match the cloud
  // RELLIS-3D ids read as SemanticKITTI ones: no truth ground, an error naming the likely cause
  // rather than a score of zero.
  const auto wrong = run_cli(args({"eval-ground", quoted(data_file("rellis3d/000001.bin")),
                                   quoted(data_file("rellis3d/000001.label"))}));
  EXPECT_EQ(wrong.exit_code, 1);
  EXPECT_NE(wrong.output.find("--classes rellis"), std::string::npos) << wrong.output;
}

}  // namespace
}  // namespace fieldlidar::test
