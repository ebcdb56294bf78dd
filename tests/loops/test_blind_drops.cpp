// Drops hidden in the blind disk (loops::mark_blind_drops): the edge of a terrace 2 m beside a
// robot that has not moved is marked from what one sweep sees beyond its blind disk; level
// ground, ground falling away past a crest, a robot on a slope, a return in the band and ground
// seen from another pose are not; the cells a robot has driven over (mark_driven) are those
// whose centres its footprint covers.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <vector>

#include <gtest/gtest.h>

#include "fieldlidar/loops/navigate_maps.hpp"

using namespace fieldlidar;

namespace {

constexpr double kMast = 1.2, kBlind = 4.5;  // a VLP-16 on a 1.2 m mast: lowest beam 15 deg

/// 20 x 20 m of 0.5 m cells around a robot at (10, 10) standing on `ground(x, y)`, tilted with
/// it (its plane's gradient there), after one sweep: a cell is seen ground when the sensor's
/// lowest beam reaches it and nothing nearer on its ray stands above the line to it.
struct Sweep {
  GridGeometry area{.resolution_m = 0.5, .origin_m = {0, 0}, .width = 40, .height = 40};
  std::function<double(double, double)> ground;
  std::vector<float> elevation, points;
  std::vector<std::uint8_t> marks;
  loops::AreaGridRules rules;

  explicit Sweep(std::function<double(double, double)> z) : ground(std::move(z)) {
    const Eigen::Vector2d robot(10, 10);
    const double h = 0.05;
    const Eigen::Vector2d grad((ground(10 + h, 10) - ground(10 - h, 10)) / (2 * h),
                               (ground(10, 10 + h) - ground(10, 10 - h)) / (2 * h));
    const Eigen::Vector3d up = Eigen::Vector3d(-grad.x(), -grad.y(), 1).normalized();
    const double sensor_z = ground(10, 10) + kMast;
    elevation.assign(area.cell_count(), NAN);
    points.assign(area.cell_count(), 0.f);
    marks.assign(area.cell_count(), 0);
    for (int iy = 0; iy < area.height; ++iy)
      for (int ix = 0; ix < area.width; ++ix) {
        const Eigen::Vector2d c = area.cell_center(ix, iy);
        const double d = (c - robot).norm();
        if (d < 0.1) continue;
        const Eigen::Vector2d u = (c - robot) / d;
        const double lowest = std::atan2(kMast, kBlind) + std::atan2(up.head<2>().dot(u), up.z());
        const double depression = std::atan2(sensor_z - ground(c.x(), c.y()), d);
        bool seen = depression <= lowest;
        for (double s = 0.1; seen && s < d - 0.25; s += 0.1) {
          const Eigen::Vector2d p = robot + s * u;
          seen = std::atan2(sensor_z - ground(p.x(), p.y()), s) >= depression - 1e-9;
        }
        if (seen) elevation[area.linear_index(ix, iy)] = float(ground(c.x(), c.y()));
        if (seen) points[area.linear_index(ix, iy)] = 10.f;
      }
    rules.sensor_xy_m = robot;
    rules.sensor_z_m = sensor_z;
    rules.sensor_height_m = kMast;
    rules.blind_radius_m = kBlind;
    rules.drop_min_m = 0.2;
    rules.blind_drop_clear_m = 1.0;
    rules.ground_normal = rules.sensor_up = up;
  }
  /// Ground at height 0 seen in cells [ix0, ix1) x [iy0, iy1] (from another pose).
  void seen_lower_ground(int ix0, int ix1, int iy0, int iy1) {
    for (int iy = iy0; iy <= iy1; ++iy)
      for (int ix = ix0; ix < ix1; ++ix) {
        elevation[area.linear_index(ix, iy)] = 0.f;
        points[area.linear_index(ix, iy)] = 5.f;
      }
  }
  void mark() { loops::mark_blind_drops(area, elevation, points, rules, marks); }
  bool marked(double x, double y) const {
    return marks[area.linear_index(int(x / 0.5), int(y / 0.5))] != 0;
  }
  int count() const { return int(std::count(marks.begin(), marks.end(), loops::kBlindDropMark)); }
};

double terrace(double x, double) {
  return x < 12.0 ? 0.5 : 0.0;
}

}  // namespace

TEST(BlindDrops, TerraceEdgeBesideTheRobotIsMarked) {
  Sweep s(terrace);
  s.mark();
  EXPECT_TRUE(s.marked(11.25, 10.25));   // the terrace's top before the edge, unseen
  EXPECT_TRUE(s.marked(12.25, 10.25));   // the foot of the edge
  EXPECT_TRUE(s.marked(15.25, 10.25));   // the shadow beyond the blind disk
  EXPECT_TRUE(s.marked(12.75, 12.25));   // off the axis
  EXPECT_FALSE(s.marked(10.25, 10.25));  // under the robot (within 1 m)
  EXPECT_FALSE(s.marked(7.75, 10.25));   // the terrace behind it: ground beyond at its level
  EXPECT_FALSE(s.marked(17.25, 10.25));  // the lower ground, seen
  EXPECT_GT(s.count(), 30);
  // Off: nothing.
  Sweep off(terrace);
  off.rules.blind_drop_clear_m = 0;
  off.mark();
  EXPECT_EQ(off.count(), 0);
}

TEST(BlindDrops, LevelGroundAndACrestAreNotDrops) {
  Sweep level([](double, double) { return 0.0; });
  level.mark();
  EXPECT_EQ(level.count(), 0);
  // Level ground to 1.5 m ahead, then falling at 5 deg: the ground seen beyond leads back up.
  Sweep crest(
      [](double x, double) { return x < 11.5 ? 0.5 : 0.5 - std::tan(0.0873) * (x - 11.5); });
  crest.mark();
  EXPECT_EQ(crest.count(), 0);
}

TEST(BlindDrops, ARobotOnASlopeReadsItsOwnPlane) {
  // 8 deg down along +x through the robot: ground lower ahead, but on the robot's plane.
  Sweep slope([](double x, double) { return -std::tan(0.1396) * (x - 10.0); });
  slope.mark();
  EXPECT_EQ(slope.count(), 0);
}

TEST(BlindDrops, AReturnInTheBandOrGroundSeenBeforeMarksNothing) {
  Sweep rock(terrace);
  rock.points[rock.area.linear_index(23, 20)] = 3.f;  // (11.75, 10.25): a return, no ground
  rock.mark();
  EXPECT_FALSE(rock.marked(13.25, 10.25));  // every ray to these crosses the rock's cell
  EXPECT_FALSE(rock.marked(15.25, 10.25));
  EXPECT_TRUE(rock.marked(11.25, 10.25));  // rays passing beside it mark the cells before it
  EXPECT_TRUE(rock.marked(13.25, 12.25));
  // The lower ground seen 2.5 m from the robot (from another pose, nearer than the lowest beam
  // reaches it from here): the band before it is no shadow of this sweep.
  Sweep before(terrace);
  before.seen_lower_ground(25, 40, 18, 22);
  before.mark();
  EXPECT_FALSE(before.marked(11.75, 10.25));
  EXPECT_FALSE(before.marked(12.25, 10.25));
  EXPECT_TRUE(before.marked(12.25, 13.25));
}

TEST(BlindDrops, TheShadowsEndAsAnApproachSweepSawIt) {
  // The robot came from 4 m behind (x = 6): from there the lowest beam meets the lower ground
  // 1.7 / tan 15 deg = 6.3 m on, at x = 12.3, as near the edge as the robot's own (x = 16.3)
  // does not reach.
  Sweep s(terrace);
  s.seen_lower_ground(24, 33, 14, 26);
  s.mark();
  EXPECT_FALSE(s.marked(11.25, 10.25));  // no shadow of this sweep: a hollow seen from aside?
  const std::vector<Eigen::Vector3d> approach{{6.0, 10.0, 1.7}};
  s.rules.earlier_sensors_m = approach;
  s.mark();
  EXPECT_TRUE(s.marked(11.25, 10.25));  // the approach's shadow: the edge between
  EXPECT_FALSE(s.marked(11.25, 6.25));  // the terrace beside the robot: ground at its level
}

TEST(BlindDrops, DrivenCellsAreThoseWhoseCentresTheFootprintCovers) {
  // The seed's 0.93 x 0.58 m chassis on 0.5 m cells: the cells whose centres it covers.
  const GridGeometry area{.resolution_m = 0.5, .origin_m = {0, 0}, .width = 40, .height = 40};
  const terrain::RobotConfig robot;
  std::vector<std::uint8_t> driven;
  loops::mark_driven(area, {10.0, 10.0, 0.0}, robot, driven);
  ASSERT_EQ(driven.size(), area.cell_count());
  EXPECT_EQ(std::count(driven.begin(), driven.end(), 1), 4);  // centres 0.25 m off both axes
  for (double x : {9.75, 10.25})
    for (double y : {9.75, 10.25})
      EXPECT_TRUE(driven[area.linear_index(int(x / 0.5), int(y / 0.5))]);
  // Along y, centred on a cell: its centre and the two along the heading, 0.5 m away, are out
  // of the 0.465 m half-length; the cells beside it (0.5 m) too.
  std::vector<std::uint8_t> along;
  loops::mark_driven(area, {10.25, 10.25, M_PI / 2}, robot, along);
  EXPECT_EQ(std::count(along.begin(), along.end(), 1), 1);
  // Marks accumulate: the first pose's cells stay.
  loops::mark_driven(area, {10.25, 10.25, M_PI / 2}, robot, driven);
  EXPECT_EQ(std::count(driven.begin(), driven.end(), 1), 4);
}
