#include <algorithm>
#include <set>
#include <vector>

#include <gtest/gtest.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/core/labels.hpp"
#include "fieldlidar/io/kitti_bin.hpp"
#include "fieldlidar/io/label_file.hpp"
#include "test_data.hpp"

using namespace fieldlidar;

TEST(Labels, RoundTripKeepsClassAndInstance) {
  std::vector<std::uint32_t> labels;
  for (std::uint16_t i = 0; i < 300; ++i)
    labels.push_back(make_label(static_cast<LabelClass>(i % 7), static_cast<std::uint16_t>(i)));
  const auto dir = test::temp_dir("labels_rt");
  io::write_labels(dir / "a.label", labels);
  EXPECT_EQ(io::read_labels(dir / "a.label"), labels);
  EXPECT_EQ(std::filesystem::file_size(dir / "a.label"), 4 * labels.size());
  EXPECT_THROW(io::write_labels(dir / "a.label", labels), Error);  // no silent overwrite
  EXPECT_THROW(io::read_labels(dir / "a.label", 299), Error);      // count must match the scan
}

TEST(Labels, SizeNotAMultipleOfFourIsAnError) {
  std::vector<std::byte> bytes(4 * 10 + 3);
  try {
    io::parse_labels(bytes, "odd.label");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("odd.label"), std::string::npos);
  }
  EXPECT_TRUE(io::parse_labels({}, "empty.label").empty());
}

TEST(Labels, RealRellisLabelsMatchTheirScan) {
  FIELDLIDAR_REQUIRE_DATA("rellis3d/000001.label");
  const auto scan = io::read_kitti_bin(test::data_file("rellis3d/000001.bin"));
  const auto labels = io::read_labels(test::data_file("rellis3d/000001.label"), scan.size());
  ASSERT_EQ(labels.size(), 131072u);
  // Only the RELLIS-3D classes of data/README.md occur.
  const std::set<std::uint32_t> known = {0, 1, 3, 4, 10, 17, 18, 19, 23, 31, 33};
  std::set<std::uint32_t> seen;
  for (auto l : labels) seen.insert(l & 0xFFFFu);
  for (auto c : seen) EXPECT_TRUE(known.count(c)) << "unexpected class " << c;
  EXPECT_TRUE(seen.count(3));  // grass
  const auto grass = std::count_if(labels.begin(), labels.end(),
                                   [](std::uint32_t l) { return (l & 0xFFFFu) == 3; });
  EXPECT_GT(grass, 10000);
}
