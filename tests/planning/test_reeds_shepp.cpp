// The Reeds–Shepp wrapper against OMPL itself: lengths, and the sampled curve against OMPL's own
// interpolation, on thousands of random pose pairs and radii.

#include <cmath>
#include <random>

#include <gtest/gtest.h>
#include <ompl/base/ScopedState.h>
#include <ompl/base/spaces/ReedsSheppStateSpace.h>

#include "fieldlidar/planning/reeds_shepp.hpp"

namespace fieldlidar::planning {
namespace {

namespace ob = ompl::base;

TEST(ReedsShepp, LengthsAndSamplesMatchOmplOnRandomPairs) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> pos(-20.0, 20.0), yaw(-M_PI, M_PI), rad(0.3, 5.0),
      frac(0.0, 1.0);
  double worst_length = 0.0, worst_end = 0.0, worst_mid = 0.0;
  int ties = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const double r = rad(rng);
    const Pose2 a{pos(rng), pos(rng), yaw(rng)}, b{pos(rng), pos(rng), yaw(rng)};
    auto space = std::make_shared<ob::ReedsSheppStateSpace>(r);
    ob::ScopedState<ob::SE2StateSpace> sa(space), sb(space), sm(space);
    sa->setXY(a.x_m, a.y_m);
    sa->setYaw(a.yaw_rad);
    sb->setXY(b.x_m, b.y_m);
    sb->setYaw(b.yaw_rad);
    const RsCurve c = reeds_shepp(a, b, r);
    worst_length =
        std::max(worst_length, std::abs(c.length_m - space->distance(sa.get(), sb.get())));
    const Pose2 end = rs_pose_at(a, c, r, c.length_m);
    worst_end = std::max({worst_end, std::hypot(end.x_m - b.x_m, end.y_m - b.y_m),
                          std::abs(wrap_angle(end.yaw_rad - b.yaw_rad))});
    const double t = frac(rng);
    space->interpolate(sa.get(), sb.get(), t, sm.get());
    const Pose2 mid = rs_pose_at(a, c, r, t * c.length_m);
    // Where two words tie in length OMPL's own interpolation (solved at radius r, not 1) may
    // take the other: the sample must then still split the curve into two shortest ones.
    const double off = std::max(std::hypot(mid.x_m - sm->getX(), mid.y_m - sm->getY()),
                                std::abs(wrap_angle(mid.yaw_rad - sm->getYaw())));
    if (off > 1e-6) {
      ++ties;
      worst_mid = std::max(worst_mid, std::abs(reeds_shepp_length_m(a, mid, r) +
                                               reeds_shepp_length_m(mid, b, r) - c.length_m));
    } else {
      worst_mid = std::max(worst_mid, off);
    }
    // the sampled curve: spacing, ends, length
    const Path p = rs_sample(a, c, r, 0.1);
    ASSERT_GE(p.size(), 2u);
    EXPECT_NEAR(p.back().pose.x_m, b.x_m, 1e-6);
    EXPECT_NEAR(p.back().pose.y_m, b.y_m, 1e-6);
    EXPECT_LE(path_length_m(p), c.length_m + 1e-6);
    EXPECT_LE(max_curvature(p), 1.0 / r * (1.0 + 1e-6));
  }
  EXPECT_LT(worst_length, 1e-9);
  EXPECT_LT(worst_end, 1e-6);
  EXPECT_LT(worst_mid, 1e-6);
  EXPECT_LT(ties, 30);  // of 3000
  RecordProperty("ties", ties);
}

// The cheap bound the search uses to skip the solver: never under the true length, and equal to
// it where the shortest curve is one of its four words.
TEST(ReedsShepp, UpperBoundIsNeverUnderTheLength) {
  std::mt19937 rng(29);
  std::uniform_real_distribution<double> pos(-20.0, 20.0), yaw(-M_PI, M_PI), rad(0.3, 5.0);
  int equal = 0;
  double mean_excess = 0.0;
  for (int trial = 0; trial < 3000; ++trial) {
    const double r = rad(rng);
    const Pose2 a{pos(rng), pos(rng), yaw(rng)}, b{pos(rng), pos(rng), yaw(rng)};
    const double ub = reeds_shepp_upper_bound_m(a, b, r), len = reeds_shepp_length_m(a, b, r);
    ASSERT_GE(ub, len - 1e-9) << trial;
    equal += ub < len + 1e-9;
    mean_excess += (ub - len) / 3000.0;
  }
  EXPECT_GT(equal, 300);         // the bound is tight often enough to save the solver
  EXPECT_LT(mean_excess, 10.0);  // and not wild elsewhere
  RecordProperty("equal", equal);
  EXPECT_NEAR(reeds_shepp_upper_bound_m({0, 0, 0}, {5, 0, 0}, 1.0), 5.0, 1e-9);
  EXPECT_NEAR(reeds_shepp_upper_bound_m({0, 0, 0}, {-3, 0, 0}, 1.0), 3.0, 1e-9);
  EXPECT_NEAR(reeds_shepp_upper_bound_m({0, 0, 0}, {0, 4, M_PI}, 2.0), M_PI * 2.0, 1e-9);
}

TEST(ReedsShepp, KnownCurves) {
  // straight ahead 5 m, straight back 3 m, a half turn left at r = 2 (pi r forward)
  EXPECT_NEAR(reeds_shepp_length_m({0, 0, 0}, {5, 0, 0}, 1.0), 5.0, 1e-9);
  EXPECT_NEAR(reeds_shepp_length_m({0, 0, 0}, {-3, 0, 0}, 1.0), 3.0, 1e-9);
  EXPECT_NEAR(reeds_shepp_length_m({0, 0, 0}, {0, 4, M_PI}, 2.0), M_PI * 2.0, 1e-9);
  const Path back = rs_sample({0, 0, 0}, reeds_shepp({0, 0, 0}, {-3, 0, 0}, 1.0), 1.0, 0.5);
  EXPECT_TRUE(back.back().reverse);
}

}  // namespace
}  // namespace fieldlidar::planning
