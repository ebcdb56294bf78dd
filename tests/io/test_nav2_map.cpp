// The nav2 map_server encoding of a traversability layer: header, row order, the three classes.

#include <cmath>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/nav2_map.hpp"

namespace fieldlidar::io {
namespace {

// map_server's reading of a pixel (negate 0, trinary): 100 occupied, 0 free, -1 unknown.
int map_server_class(unsigned char p, const Nav2MapConfig& c) {
  const double occ = (255.0 - p) / 255.0;
  if (occ > c.occupied_thresh) return 100;
  if (occ <= c.free_thresh) return 0;
  return -1;
}

Grid2D three_by_two() {
  GridGeometry g;
  g.resolution_m = 0.5;
  g.origin_m = {-1.5, 2.0};
  g.width = 3;
  g.height = 2;
  Grid2D grid(g);
  auto tau = grid.add_layer("tau", std::numeric_limits<float>::quiet_NaN());
  tau[g.linear_index(0, 0)] = 0.0f;  // bottom row: impassable, best, unknown
  tau[g.linear_index(1, 0)] = 1.0f;
  tau[g.linear_index(0, 1)] = 0.9f;  // top row: good, poor, unknown
  tau[g.linear_index(1, 1)] = 0.2f;
  return grid;
}

TEST(Nav2Map, HeaderRowOrderAndThreeClasses) {
  const Nav2MapConfig cfg;
  const Nav2Map m = encode_nav2_map(three_by_two(), "tau", "map.pgm", cfg);
  const std::string head = "P5\n# fieldlidar traversability, 0.5 m cells\n3 2\n255\n";
  ASSERT_EQ(m.pgm.substr(0, head.size()), head);
  ASSERT_EQ(m.pgm.size(), head.size() + 6);
  auto px = [&](int row, int col) { return (unsigned char)m.pgm[head.size() + row * 3 + col]; };
  // Row 0 of the image is the top of the map (iy = 1).
  EXPECT_EQ(px(0, 0), kNav2Free);      // tau 0.9
  EXPECT_EQ(px(0, 1), kNav2Occupied);  // tau 0.2: cost 0.8 > 0.65
  EXPECT_EQ(px(0, 2), kNav2Unknown);
  EXPECT_EQ(px(1, 0), kNav2Occupied);  // tau 0
  EXPECT_EQ(px(1, 1), kNav2Free);      // tau 1
  EXPECT_EQ(px(1, 2), kNav2Unknown);
  // As map_server reads them: unknown stays unknown (not free), the others as meant.
  EXPECT_EQ(map_server_class(kNav2Unknown, cfg), -1);
  EXPECT_EQ(map_server_class(kNav2Free, cfg), 0);
  EXPECT_EQ(map_server_class(kNav2Occupied, cfg), 100);
  EXPECT_NE(m.yaml.find("image: map.pgm\n"), std::string::npos) << m.yaml;
  EXPECT_NE(m.yaml.find("resolution: 0.5\n"), std::string::npos) << m.yaml;
  EXPECT_NE(m.yaml.find("origin: [-1.5, 2, 0.0]\n"), std::string::npos) << m.yaml;
  EXPECT_NE(m.yaml.find("negate: 0\n"), std::string::npos);
  EXPECT_NE(m.yaml.find("occupied_thresh: 0.65\n"), std::string::npos);
  EXPECT_NE(m.yaml.find("free_thresh: 0.196\n"), std::string::npos);
  EXPECT_NE(m.yaml.find("mode: trinary\n"), std::string::npos);
}

TEST(Nav2Map, ScaleKeepsTheCostAndRefusesBadInput) {
  Nav2MapConfig cfg;
  cfg.mode = "scale";
  const Nav2Map m = encode_nav2_map(three_by_two(), "tau", "map.pgm", cfg);
  const std::size_t h = m.pgm.size() - 6;
  EXPECT_EQ((unsigned char)m.pgm[h + 0], 229);  // round(254 * 0.9)
  EXPECT_EQ((unsigned char)m.pgm[h + 1], 51);   // round(254 * 0.2)
  EXPECT_EQ((unsigned char)m.pgm[h + 3], 0);
  EXPECT_EQ((unsigned char)m.pgm[h + 4], 254);
  EXPECT_EQ((unsigned char)m.pgm[h + 5], kNav2Unknown);
  EXPECT_THROW(encode_nav2_map(three_by_two(), "slope", "m.pgm"), Error);
  cfg.mode = "raw";
  EXPECT_THROW(encode_nav2_map(three_by_two(), "tau", "m.pgm", cfg), Error);
  EXPECT_THROW(encode_nav2_map(Grid2D(GridGeometry{}), "tau", "m.pgm"), Error);
}

}  // namespace
}  // namespace fieldlidar::io

namespace fieldlidar::io {
namespace {

TEST(Nav2MapRead, DecodesWhatIsEncodedInBothModes) {
  GridGeometry g;
  g.resolution_m = 0.5;
  g.origin_m = {-1.5, 2.0};
  g.width = 3;
  g.height = 2;
  Grid2D grid(g);
  auto tau = grid.add_layer("tau", std::numeric_limits<float>::quiet_NaN());
  tau[g.linear_index(0, 0)] = 0.0f;
  tau[g.linear_index(1, 0)] = 1.0f;
  tau[g.linear_index(0, 1)] = 0.9f;
  tau[g.linear_index(1, 1)] = 0.2f;
  for (const std::string mode : {"trinary", "scale"}) {
    Nav2MapConfig c;
    c.mode = mode;
    const Nav2Map m = encode_nav2_map(grid, "tau", "map.pgm", c);
    const Grid2D back = decode_nav2_map(m.yaml, m.pgm, "tau", "map.yaml");
    EXPECT_EQ(back.geometry().width, 3);
    EXPECT_EQ(back.geometry().height, 2);
    EXPECT_DOUBLE_EQ(back.geometry().origin_m.x(), -1.5);
    EXPECT_DOUBLE_EQ(back.geometry().origin_m.y(), 2.0);
    const auto t = back.layer("tau");
    EXPECT_EQ(t[g.linear_index(0, 0)], 0.0f) << mode;
    EXPECT_EQ(t[g.linear_index(1, 0)], 1.0f) << mode;
    EXPECT_TRUE(std::isnan(t[g.linear_index(2, 0)])) << mode;
    EXPECT_TRUE(std::isnan(t[g.linear_index(2, 1)])) << mode;
    if (mode == "scale")
      EXPECT_NEAR(t[g.linear_index(1, 1)], 0.2f, 0.005f);
    else
      EXPECT_EQ(t[g.linear_index(1, 1)], 0.0f);  // cost 0.8 > 0.65: occupied
  }
}

TEST(Nav2MapRead, MalformedFilesNameTheField) {
  const std::string pgm = "P5\n1 1\n255\n\xfe";
  EXPECT_THROW(decode_nav2_map("image: a.pgm\n", pgm, "tau", "a.yaml"), Error);  // no resolution
  EXPECT_THROW(decode_nav2_map("resolution: x\n", pgm, "tau", "a.yaml"), Error);
  EXPECT_THROW(decode_nav2_map("resolution: 0.5\n", "P2\n1 1\n255\n1", "tau", "a.yaml"), Error);
  EXPECT_THROW(decode_nav2_map("resolution: 0.5\n", "P5\n4 4\n255\n\x01", "tau", "a.yaml"), Error);
  EXPECT_EQ(decode_nav2_map("resolution: 0.5\n", pgm, "tau", "a.yaml").layer("tau")[0], 1.0f);
}

TEST(Nav2MapRead, NegateAndThresholdsOutOfRangeNameTheField) {
  const std::string pgm = "P5\n1 1\n255\n\xfe";
  const struct {
    std::string yaml, message;
  } cases[] = {
      {"negate: 5\n", "a.yaml: negate 5 must be 0 or 1"},
      {"occupied_thresh: 0.1\nfree_thresh: 0.9\n",
       "a.yaml: occupied_thresh 0.1 must be above free_thresh 0.9"},
      {"free_thresh: 0.7\n",
       "a.yaml: occupied_thresh 0.65 (default) must be above free_thresh 0.7"},
      {"occupied_thresh: 1.5\n", "a.yaml: occupied_thresh 1.5 must be in [0, 1]"},
      {"free_thresh: -0.1\n", "a.yaml: free_thresh -0.1 must be in [0, 1]"},
  };
  for (const auto& c : cases) {
    try {
      decode_nav2_map("resolution: 0.5\n" + c.yaml, pgm, "tau", "a.yaml");
      ADD_FAILURE() << c.yaml << " was accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(c.message), std::string::npos) << e.what();
    }
  }
  // negate: 1 reads the image the other way round.
  EXPECT_EQ(decode_nav2_map("resolution: 0.5\nnegate: 1\n", pgm, "tau", "a.yaml").layer("tau")[0],
            0.0f);
}

}  // namespace
}  // namespace fieldlidar::io
