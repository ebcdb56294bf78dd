// End-to-end: what fieldlidar says about input it cannot take. Each failure names the real
// problem (the span of far-flung coordinates in metres, an unknown sensor with the presets, the
// missing file) with exit status 1.

#include <cmath>
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

// Coordinates of 1e25 to 1e30 m (another unit, or garbage): refused with the span, never a
// negative cell count from an overflowed conversion, nor 0 ground and exit 0.
TEST(CliInputMessages, FarFlungCoordinatesAreRefusedWithTheirSpan) {
  const auto dir = test::temp_dir("cli_far_flung");
  const auto huge = dir / "huge.bin";
  {
    std::vector<float> pts;
    for (int i = 0; i < 200; ++i) {
      const float a = 0.0314f * float(i);
      pts.insert(pts.end(), {1e30f * std::cos(a), 1e30f * std::sin(a), 1e25f * float(i % 7), 0});
    }
    std::ofstream(huge, std::ios::binary)
        .write(reinterpret_cast<const char*>(pts.data()),
               static_cast<std::streamsize>(pts.size() * sizeof(float)));
  }
  const std::string in = test::quoted(huge);
  for (const std::string& args :
       {"segment " + in, "segment " + in + " --method robust --sensor hdl64e",
        "segment " + in + " --method seed002 --sensor hdl64e --clusters range-image",
        "trunks " + in + " --out " + test::quoted(dir / "trunks"),
        "traversability " + in + " --out " + test::quoted(dir / "map")}) {
    const auto r = test::run_cli(args);
    EXPECT_EQ(r.exit_code, 1) << args << "\n" << r.output;
    EXPECT_NE(r.output.find("fieldlidar: error: " + huge.string() + ": the points span 2e+30 x"),
              std::string::npos)
        << args << "\n"
        << r.output;
    EXPECT_NE(r.output.find("coordinates in another unit than metres"), std::string::npos)
        << args << "\n"
        << r.output;
    EXPECT_EQ(r.output.find("-2147483648"), std::string::npos) << args << "\n" << r.output;
    EXPECT_EQ(r.output.find("give a larger cell"), std::string::npos) << args << "\n" << r.output;
  }
}

TEST(CliInputMessages, UnknownSensorIsNamedWithThePresets) {
  const auto dir = test::temp_dir("cli_bogus_sensor");
  for (const std::string& args :
       {"legs x.bin --sensor bogus --out " + test::quoted(dir / "legs.csv"),
        "trunks x.las --sensor bogus --out " + test::quoted(dir / "trunks")}) {
    const auto r = test::run_cli(args);
    EXPECT_EQ(r.exit_code, 1) << args << "\n" << r.output;
    EXPECT_EQ(r.output.rfind("fieldlidar: error: --sensor: 'bogus' is not a known sensor preset "
                             "(vlp16, vlp32c, hdl32e, hdl64e, os1-64,",
                             0),
              0u)
        << args << "\n"
        << r.output;
  }
  EXPECT_TRUE(fs::is_empty(dir));
}

TEST(CliInputMessages, MissingOdomFileOfAReplayIsNamed) {
  const auto dir = test::temp_dir("cli_replay_odom");
  fs::create_directories(dir / "sim" / "pcd");
  std::ofstream(dir / "sim" / "times.txt") << "0\n";
  const auto missing = dir / "nope" / "poses_tum.txt";
  const auto r =
      test::run_cli("follow --max-time 2 --replay " + test::quoted(dir / "sim") + " --odom " +
                    test::quoted(missing) + " --out " + test::quoted(dir / "out"));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("fieldlidar: error: --odom " + missing.string() + ": no such file"),
            std::string::npos)
      << r.output;
}

}  // namespace
}  // namespace fieldlidar
