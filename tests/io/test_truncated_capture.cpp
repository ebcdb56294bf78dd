// A capture cut inside a record (its recorder killed): every sweep before the cut is read, the
// lost tail is reported through FrameSource::warnings(), never as a failure of the whole file.

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/frame_source.hpp"
#include "fieldlidar/io/pcap.hpp"
#include "test_data.hpp"

namespace fieldlidar {
namespace {

namespace fs = std::filesystem;

/// The first `bytes` bytes of `capture` as a file in `dir`.
fs::path cut_copy(const fs::path& capture, std::size_t bytes, const fs::path& dir) {
  std::ifstream in(capture, std::ios::binary);
  std::vector<char> head(bytes);
  in.read(head.data(), static_cast<std::streamsize>(bytes));
  const auto out = dir / ("cut_" + std::to_string(bytes) + ".pcap");
  std::ofstream(out, std::ios::binary).write(head.data(), in.gcount());
  return out;
}

struct Read {
  std::vector<std::size_t> complete_sizes;  ///< points of each complete sweep, in order
  std::size_t partial = 0;
  std::vector<std::string> warnings;
};

Read read_all(const fs::path& capture, const fs::path& metadata = {}) {
  io::SourceOptions o;
  o.metadata = metadata;
  auto source = io::FrameSource::open(capture, o);
  Read r;
  while (auto f = source->next()) {
    if (f->complete)
      r.complete_sizes.push_back(f->cloud.size());
    else
      ++r.partial;
  }
  r.warnings = source->warnings();
  return r;
}

TEST(TruncatedCapture, VelodyneSweepsBeforeTheCutAreRead) {
  const std::string name = "velodyne_pcap/hdl32_example.pcap";
  FIELDLIDAR_REQUIRE_DATA(name);
  const auto full = read_all(test::data_file(name));
  ASSERT_EQ(full.complete_sizes.size(), 5u);
  EXPECT_TRUE(full.warnings.empty());
  const auto dir = test::temp_dir("truncated_velodyne");
  // 300000 bytes: inside record 251 (the first complete sweep ends before it); 800000 bytes: later.
  for (const std::size_t bytes : {300000u, 800000u}) {
    const auto cut = read_all(cut_copy(test::data_file(name), bytes, dir));
    ASSERT_EQ(cut.warnings.size(), 1u) << bytes;
    EXPECT_NE(cut.warnings[0].find("ends inside record"), std::string::npos) << cut.warnings[0];
    ASSERT_GE(cut.complete_sizes.size(), 1u) << bytes;
    ASSERT_LT(cut.complete_sizes.size(), full.complete_sizes.size()) << bytes;
    for (std::size_t i = 0; i < cut.complete_sizes.size(); ++i)
      EXPECT_EQ(cut.complete_sizes[i], full.complete_sizes[i]) << bytes << " sweep " << i;
    EXPECT_GE(cut.partial, 1u);  // the sweep the cut went through
  }
}

TEST(TruncatedCapture, OusterSweepsBeforeTheCutAreRead) {
  const std::string name = "ouster_pcap/OS-1-64_1024x10_fw20.pcap";
  const std::string meta = "ouster_pcap/2_0_0_os1-991913000010-64.json";
  FIELDLIDAR_REQUIRE_DATA(name);
  FIELDLIDAR_REQUIRE_DATA(meta);
  const auto full = read_all(test::data_file(name), test::data_file(meta));
  ASSERT_GE(full.complete_sizes.size(), 1u);
  EXPECT_TRUE(full.warnings.empty());
  const auto dir = test::temp_dir("truncated_ouster");
  const auto size = fs::file_size(test::data_file(name));
  const auto cut =
      read_all(cut_copy(test::data_file(name), size - 5000, dir), test::data_file(meta));
  ASSERT_EQ(cut.warnings.size(), 1u);
  EXPECT_NE(cut.warnings[0].find("ends inside record"), std::string::npos) << cut.warnings[0];
  ASSERT_GE(cut.complete_sizes.size() + 1, full.complete_sizes.size());
  for (std::size_t i = 0; i < cut.complete_sizes.size(); ++i)
    EXPECT_EQ(cut.complete_sizes[i], full.complete_sizes[i]) << "sweep " << i;
}

TEST(TruncatedCapture, ReaderStopsAtTheCutAndSaysWhere) {
  const std::string name = "velodyne_pcap/velodyne_example.pcap";
  FIELDLIDAR_REQUIRE_DATA(name);
  const auto dir = test::temp_dir("truncated_reader");
  const auto whole = fs::file_size(test::data_file(name));
  std::size_t full_count = 0;
  {
    io::PcapReader reader(test::data_file(name));
    while (reader.next()) ++full_count;
    EXPECT_FALSE(reader.truncated());
  }
  // Cuts inside a record header (24-byte file header + 16-byte record header + payload...) and
  // inside a record body: every datagram before the cut, then a clean end with the reason.
  for (const std::size_t bytes : {std::size_t(24 + 10), std::size_t(whole / 2), whole - 1}) {
    io::PcapReader reader(cut_copy(test::data_file(name), bytes, dir));
    std::size_t n = 0;
    while (reader.next()) ++n;
    ASSERT_TRUE(reader.truncated()) << bytes;
    EXPECT_NE(reader.truncated()->find("ends inside record"), std::string::npos)
        << *reader.truncated();
    EXPECT_LT(n, full_count);
    EXPECT_FALSE(reader.next());  // stays at the end
  }
}

TEST(TruncatedCapture, CutBeforeAnyDatagramIsAnErrorThatSaysSo) {
  const std::string name = "velodyne_pcap/hdl32_example.pcap";
  FIELDLIDAR_REQUIRE_DATA(name);
  const auto cut = cut_copy(test::data_file(name), 500, test::temp_dir("truncated_first"));
  try {
    io::FrameSource::open(cut);
    FAIL() << "a capture without one whole datagram cannot be read";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("ends inside record 0"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace fieldlidar
