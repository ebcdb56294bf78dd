// Drop bands (loops::mark_drop_bands): the foot of a step down, hidden by its lip from a robot
// above it, is marked impassable until seen; gaps between rings, a face seen from below, the
// shadow of a rock and the blind disk are not.
#include <cmath>
#include <cstdint>
#include <vector>

#include <gtest/gtest.h>

#include "fieldlidar/loops/navigate_maps.hpp"

using namespace fieldlidar;

namespace {

/// 20 x 20 m of 0.5 m cells: ground at `high_m` for x < 10 m, no return over x in [10, 11.5),
/// ground at `low_m` beyond; nothing blocked.
struct Field {
  GridGeometry area{.resolution_m = 0.5, .origin_m = {0, 0}, .width = 40, .height = 40};
  std::vector<float> elevation, points;
  std::vector<std::uint8_t> blocked, marks;

  float high = 0;

  Field(float high_m, float low_m, double band_end_m = 11.5) : high(high_m) {
    elevation.assign(area.cell_count(), NAN);
    points.assign(area.cell_count(), 0.f);
    blocked.assign(area.cell_count(), 0);
    marks.assign(area.cell_count(), 0);
    for (int iy = 0; iy < area.height; ++iy)
      for (int ix = 0; ix < area.width; ++ix) {
        const double x = area.cell_center(ix, iy).x();
        const std::size_t i = area.linear_index(ix, iy);
        if (x < 10.0) elevation[i] = high_m, points[i] = 20.f;
        if (x >= band_end_m) elevation[i] = low_m, points[i] = 20.f;
      }
  }
  /// The sensor `mast_m` above the ground it stands on, the higher unless `ground_m` says
  /// otherwise.
  void mark(const Eigen::Vector2d& sensor_m, double mast_m = 1.2, double ground_m = NAN) {
    loops::AreaGridRules rules;
    rules.sensor_xy_m = sensor_m;
    rules.sensor_z_m = (std::isfinite(ground_m) ? ground_m : high) + mast_m;
    rules.sensor_height_m = mast_m;
    rules.blind_radius_m = 4.5;
    rules.drop_band_max_m = 3.0;
    rules.drop_min_m = 0.2;
    rules.drop_radius_m = 12.0;
    loops::mark_drop_bands(area, elevation, points, blocked, rules, marks);
  }
  bool marked(double x, double y) const {
    return marks[area.linear_index(int(x / 0.5), int(y / 0.5))] != 0;
  }
  int count() const {
    int n = 0;
    for (auto m : marks) n += m;
    return n;
  }
};

}  // namespace

TEST(DropBands, FootOfAStepSeenFromAboveIsMarked) {
  Field f(0.5f, 0.0f);
  f.mark({4.0, 10.0});
  EXPECT_TRUE(f.marked(10.25, 10.25));
  EXPECT_TRUE(f.marked(11.25, 10.25));
  EXPECT_TRUE(f.marked(10.75, 13.25));   // off the sensor's axis, along its ray's diagonal
  EXPECT_FALSE(f.marked(10.75, 19.75));  // beyond the 12 m looked at
  EXPECT_FALSE(f.marked(9.75, 10.25));   // the lip is ground
  EXPECT_FALSE(f.marked(11.75, 10.25));  // and the ground beyond
  const int n = f.count();
  EXPECT_GT(n, 40);
  // A mark stays from farther on, inside the blind disk, until the cell is seen.
  f.mark({8.0, 10.0});
  EXPECT_EQ(f.count(), n);
  f.points[f.area.linear_index(20, 20)] = 3.f;
  f.mark({8.0, 10.0});
  EXPECT_FALSE(f.marked(10.25, 10.25));
  EXPECT_EQ(f.count(), n - 1);
}

TEST(DropBands, GapsFacesRocksAndTheBlindDiskAreNot) {
  {  // level ground either side: the gap between two rings
    Field f(0.05f, 0.0f);
    f.mark({4.0, 10.0});
    EXPECT_EQ(f.count(), 0);
  }
  {  // a downslope of 8.5 deg with a gap between two rings, the ray to its top 19 deg (on the
     // sensor's axis; farther off it the ray flattens and the band turns into a shadow)
    Field f(0.3f, 0.0f);
    f.mark({4.0, 10.0}, 2.0);
    EXPECT_FALSE(f.marked(10.25, 10.25));
    EXPECT_FALSE(f.marked(11.25, 10.25));
    Field g(0.3f, 0.0f);
    g.mark({4.0, 10.0}, 0.6);  // a sensor 0.6 m up: the ray 6 deg, the band a shadow
    EXPECT_TRUE(g.marked(10.25, 10.25));
  }
  {  // a raised terrace seen from the ground below it: its far edge is no drop the robot meets
    Field f(0.5f, 0.0f);
    f.mark({4.0, 10.0}, 1.2, 0.0);
    EXPECT_EQ(f.count(), 0);
  }
  {  // the step seen from below: its face, not a shadow
    Field f(0.5f, 0.0f);
    f.mark({16.0, 10.0});
    EXPECT_EQ(f.count(), 0);
  }
  {  // the higher side is blocked (a rock's top kept as ground): its own shadow
    Field f(0.5f, 0.0f);
    for (int iy = 0; iy < f.area.height; ++iy) f.blocked[f.area.linear_index(19, iy)] = 1;
    f.mark({4.0, 10.0});
    EXPECT_EQ(f.count(), 0);
  }
  {  // the band in the blind disk: unseen for want of a beam
    Field f(0.5f, 0.0f);
    f.mark({8.0, 10.0});
    EXPECT_FALSE(f.marked(10.25, 10.25));
    EXPECT_FALSE(f.marked(11.25, 10.25));
  }
  {  // wider than drop_band_max_m: a gap between far rings on a slope
    Field f(0.5f, 0.0f, 13.5);
    f.mark({4.0, 10.0});
    EXPECT_EQ(f.count(), 0);
  }
  {  // the band seen edge-on (the sensor's ray along it): no line across it follows the ray
    Field f(0.5f, 0.0f);
    f.mark({10.75, 3.0});
    EXPECT_FALSE(f.marked(10.75, 12.25));
  }
}
