// End-to-end: `fieldlidar info` and `convert` on captures and bags.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "fieldlidar/io/cloud_file.hpp"
#include "run_cli.hpp"
#include "test_data.hpp"

namespace fieldlidar {
namespace {

nlohmann::json info_json(const std::string& args) {
  const auto r = test::run_cli("info --json " + args);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return nlohmann::json::parse(r.output);
}

TEST(CliStreams, InfoReportsScanAndPoseArrayCountsOfALegBag) {
  FIELDLIDAR_REQUIRE_DATA("legs_2d/positive_1_extracted.bag");
  const auto j = info_json(test::quoted(test::data_file("legs_2d/positive_1_extracted.bag")));
  EXPECT_EQ(j["format"], "rosbag");
  // Counts from the bag's index (rosbag_storage), one annotation per scan.
  EXPECT_EQ(j["topics"]["/training_scan"].get<int>(), 197);
  EXPECT_EQ(j["topics"]["/leg_cluster_positions"].get<int>(), 197);
  EXPECT_EQ(j["topic_types"]["/leg_cluster_positions"], "geometry_msgs/PoseArray");
  EXPECT_EQ(j["frames"].get<int>(), 197);
  EXPECT_EQ(j["rings"].get<int>(), 1);
  // Total over the frames, with per-frame statistics.
  EXPECT_GT(j["points"].get<long>(), 197 * 500);
  EXPECT_LE(j["per_frame"]["points_min"].get<long>(), j["per_frame"]["points_max"].get<long>());
}

TEST(CliStreams, InfoOnVelodyneAndOusterCaptures) {
  FIELDLIDAR_REQUIRE_DATA("velodyne_pcap/hdl32_example.pcap");
  const auto v = info_json(test::quoted(test::data_file("velodyne_pcap/hdl32_example.pcap")));
  EXPECT_EQ(v["format"], "velodyne-pcap");
  EXPECT_EQ(v["sensor"], "hdl32e");
  EXPECT_EQ(v["frames"].get<int>(), 5);
  EXPECT_EQ(v["partial_frames"].get<int>(), 2);
  EXPECT_EQ(v["rings"].get<int>(), 32);
  EXPECT_NEAR(v["per_frame"]["period_s_mean"].get<double>(), 0.0853, 0.002);
  FIELDLIDAR_REQUIRE_DATA("ouster_pcap/OS-2-128-U1_v2.3.0_1024x10.pcap");
  const auto o =
      info_json(test::quoted(test::data_file("ouster_pcap/OS-2-128-U1_v2.3.0_1024x10.pcap")));
  EXPECT_EQ(o["format"], "ouster-pcap");
  EXPECT_EQ(o["frames"].get<int>(), 1);
  EXPECT_EQ(o["rings"].get<int>(), 128);
  EXPECT_EQ(o["points"].get<int>(), 131072);
  EXPECT_EQ(o["organized"]["height"].get<int>(), 128);
  EXPECT_GE(o["imu_samples"].get<int>(), 10);
}

TEST(CliStreams, MissingTopicFailsClearlyAndACutCaptureWarns) {
  FIELDLIDAR_REQUIRE_DATA("legs_2d/negative_2.bag");
  auto r = test::run_cli("info " + test::quoted(test::data_file("legs_2d/negative_2.bag")) +
                         " --topic /nope");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("fieldlidar: error:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("/left_scan"), std::string::npos) << r.output;

  FIELDLIDAR_REQUIRE_DATA("velodyne_pcap/velodyne_example.pcap");
  const auto dir = test::temp_dir("cli_streams_corrupt");
  std::ifstream in(test::data_file("velodyne_pcap/velodyne_example.pcap"), std::ios::binary);
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), {});
  bytes.resize(bytes.size() - 700);
  std::ofstream(dir / "cut.pcap", std::ios::binary)
      .write(bytes.data(), std::streamsize(bytes.size()));
  // Cut mid-record (a killed recorder): read up to the cut, with a warning.
  r = test::run_cli("info " + test::quoted(dir / "cut.pcap"));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("fieldlidar: warning:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("truncated"), std::string::npos) << r.output;
}

TEST(CliStreams, ConvertCaptureToFramesKeepsRingAndTimeAndRefusesToOverwrite) {
  FIELDLIDAR_REQUIRE_DATA("velodyne_pcap/hdl32_example.pcap");
  const auto dir = test::temp_dir("cli_streams_convert");
  const auto pcap = test::quoted(test::data_file("velodyne_pcap/hdl32_example.pcap"));
  auto r = test::run_cli("convert " + pcap + " " + test::quoted(dir / "pcd"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (int i = 0; i < 5; ++i)
    EXPECT_TRUE(std::filesystem::exists(dir / "pcd" / ("00000" + std::to_string(i) + ".pcd")));
  EXPECT_FALSE(std::filesystem::exists(dir / "pcd" / "000005.pcd"));  // partial sweeps skipped
  const auto cloud = io::read_cloud(dir / "pcd" / "000001.pcd");
  EXPECT_GT(cloud.size(), 40000u);
  EXPECT_TRUE(cloud.fields.ring);
  EXPECT_TRUE(cloud.fields.time);
  EXPECT_EQ(cloud.ring_count(), 32u);
  float tmax = 0;
  for (const auto& p : cloud.points) tmax = std::max(tmax, p.time);
  EXPECT_NEAR(tmax, 0.0853, 0.002);
  std::ifstream times(dir / "pcd" / "times.txt");
  int lines = 0;
  for (std::string line; std::getline(times, line);) ++lines;
  EXPECT_EQ(lines, 5);

  // Again without --force: refused, the message names the existing file.
  r = test::run_cli("convert " + pcap + " " + test::quoted(dir / "pcd"));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("fieldlidar: error:"), std::string::npos) << r.output;
  r = test::run_cli("convert --force " + pcap + " " + test::quoted(dir / "pcd"));
  EXPECT_EQ(r.exit_code, 0) << r.output;

  // KITTI .bin frames, partial sweeps included on request.
  r = test::run_cli("convert --format bin --partial " + pcap + " " + test::quoted(dir / "bin"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(std::filesystem::exists(dir / "bin" / "000006.bin"));
  EXPECT_EQ(io::read_cloud(dir / "bin" / "000002.bin").size(),
            io::read_cloud(dir / "pcd" / "000001.pcd").size());
}

TEST(CliStreams, ConvertBagScansToFrames) {
  FIELDLIDAR_REQUIRE_DATA("legs_2d/positive_2_extracted.bag");
  const auto dir = test::temp_dir("cli_streams_bag");
  const auto r =
      test::run_cli("convert " + test::quoted(test::data_file("legs_2d/positive_2_extracted.bag")) +
                    " " + test::quoted(dir / "scans") + " --format bin");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::size_t files = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir / "scans"))
    files += e.path().extension() == ".bin";
  const auto j = info_json(test::quoted(test::data_file("legs_2d/positive_2_extracted.bag")));
  EXPECT_EQ(files, j["frames"].get<std::size_t>());
}

}  // namespace
}  // namespace fieldlidar
