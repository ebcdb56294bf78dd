// people::person_bodies on columns of returns built in code: a person (legs, torso, nothing
// above the head), a post (returns up past a head's height), a bicycle rack (nothing above the
// legs), an edge just over 1.1 m high (a torso band barely reached), seen by a car-roof sensor
// and by a low mower sensor that cannot see a chest nearby.

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "fieldlidar/people/body_check.hpp"

namespace fieldlidar::people {
namespace {

// Returns of a vertical column (radius 0.15 m) at `at` from the ground to `top_m` above it, on
// every ring of `sensor` (at `height_m` above the ground) that meets it.
void add_column(PointCloud& cloud, const SensorModel& sensor, double height_m,
                const Eigen::Vector2d& at, double top_m) {
  const double r = at.norm();
  for (std::size_t k = 0; k < sensor.rings(); ++k) {
    const double z = height_m + r * std::tan(sensor.beam_altitudes_rad[k]);
    if (z < 0 || z > top_m) continue;
    for (int j = -2; j <= 2; ++j) {
      const Eigen::Vector2d p = at + Eigen::Vector2d(-at.y(), at.x()).normalized() * 0.05 * j;
      Point q{float(p.x()), float(p.y()), float(z - height_m)};
      q.ring = std::uint16_t(k);
      cloud.push_back(q);
    }
  }
}

TEST(BodyCheck, PersonKeptPostAndRackDropped) {
  const SensorModel roof = SensorModel::hdl64e();
  const double h = 1.73;
  PointCloud cloud;
  cloud.fields.ring = true;
  // The roof sensor's highest beam (+2 deg) passes 2.1 m only beyond 10.6 m: the post stands at
  // 15 m.
  const Eigen::Vector2d person(8.0, 1.0), post(15.0, -2.0), rack(7.0, 4.0);
  add_column(cloud, roof, h, person, 1.75);
  add_column(cloud, roof, h, post, 3.0);
  add_column(cloud, roof, h, rack, 0.8);
  std::vector<Person> pairs(3);
  pairs[0].position_m = person;
  pairs[1].position_m = post;
  pairs[2].position_m = rack;
  const auto body = person_bodies(cloud, roof, h, pairs);
  ASSERT_EQ(body.size(), 3u);
  EXPECT_TRUE(body[0]);
  EXPECT_FALSE(body[1]);  // goes on above a head
  EXPECT_FALSE(body[2]);  // nothing at chest height, where the beams pass
  BodyCheckConfig off;
  off.enabled = false;
  for (const char b : person_bodies(cloud, roof, h, pairs, off)) EXPECT_TRUE(b);
}

// Something a little over 1.1 m high (a car's door edge, a box, a bumper on a trailer) reaches
// into the torso band on a few of the beams that cross it; a body covers it on nearly all.
TEST(BodyCheck, TorsoOnAFewOfTheCrossingBeamsIsNoBody) {
  const SensorModel roof = SensorModel::hdl64e();
  const double h = 1.73;
  PointCloud cloud;
  cloud.fields.ring = true;
  const Eigen::Vector2d person(9.0, 1.0), edge(9.0, -3.0);
  add_column(cloud, roof, h, person, 1.75);
  add_column(cloud, roof, h, edge, 1.3);
  std::vector<Person> pairs(2);
  pairs[0].position_m = person;
  pairs[1].position_m = edge;
  const auto body = person_bodies(cloud, roof, h, pairs);
  EXPECT_TRUE(body[0]);
  EXPECT_FALSE(body[1]);
  BodyCheckConfig rings_only;  // two rings in the band, whatever crosses it: taken for a body
  rings_only.torso_ring_fraction = 0.0;
  EXPECT_TRUE(person_bodies(cloud, roof, h, pairs, rings_only)[1]);
}

// A VLP-16 0.4 m above a lawn sees a chest only from a few metres out: a person 1.5 m ahead shows
// legs alone and is kept; a rack 6 m away, where the upper beams cross the chest band, is not.
TEST(BodyCheck, TorsoNotAskedWhereNoBeamCrossesIt) {
  const SensorModel low = SensorModel::vlp16();
  const double h = 0.4;
  PointCloud cloud;
  cloud.fields.ring = true;
  const Eigen::Vector2d near(1.5, 0.0), far(6.0, 0.0);
  add_column(cloud, low, h, near, 0.9);  // what the beams meet of a person 1.5 m away: legs
  add_column(cloud, low, h, far, 0.8);   // a rack 6 m away: the upper beams pass over it
  std::vector<Person> pairs(2);
  pairs[0].position_m = near;
  pairs[1].position_m = far;
  const auto body = person_bodies(cloud, low, h, pairs);
  EXPECT_TRUE(body[0]);
  EXPECT_FALSE(body[1]);
}

}  // namespace
}  // namespace fieldlidar::people
