// A capture cut mid-record (recorder killed): info and convert read every sweep before the cut,
// warn about the lost tail and succeed.

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "run_cli.hpp"
#include "test_data.hpp"

namespace fieldlidar {
namespace {

namespace fs = std::filesystem;

TEST(CliTruncatedCapture, InfoAndConvertReadUpToTheCut) {
  const std::string name = "velodyne_pcap/hdl32_example.pcap";
  FIELDLIDAR_REQUIRE_DATA(name);
  const auto dir = test::temp_dir("cli_truncated_capture");
  const auto cut = dir / "cut.pcap";
  {
    std::ifstream in(test::data_file(name), std::ios::binary);
    // 800000 of 1164288 bytes: inside record 670; 3 complete sweeps before the cut (of 5).
    std::vector<char> head(800000);
    in.read(head.data(), static_cast<std::streamsize>(head.size()));
    std::ofstream(cut, std::ios::binary).write(head.data(), in.gcount());
  }
  const auto info = test::run_cli("info " + test::quoted(cut));
  ASSERT_EQ(info.exit_code, 0) << info.output;
  EXPECT_NE(info.output.find("frames:  3 (+2 partial"), std::string::npos) << info.output;
  EXPECT_NE(info.output.find("fieldlidar: warning: " + cut.string() + ": the capture ends inside"),
            std::string::npos)
      << info.output;
  const auto json = test::run_cli("info --json " + test::quoted(cut) + " 2>/dev/null");
  EXPECT_NE(json.output.find("\"warnings\""), std::string::npos) << json.output;

  const auto out = dir / "frames";
  const auto conv = test::run_cli("convert -q " + test::quoted(cut) + " " + test::quoted(out));
  ASSERT_EQ(conv.exit_code, 0) << conv.output;
  EXPECT_NE(conv.output.find("wrote 3 frames"), std::string::npos) << conv.output;
  EXPECT_NE(conv.output.find("fieldlidar: warning:"), std::string::npos) << conv.output;
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(fs::exists(out / ("00000" + std::to_string(i) + ".pcd")));
  EXPECT_FALSE(fs::exists(out / "000003.pcd"));
}

}  // namespace
}  // namespace fieldlidar
