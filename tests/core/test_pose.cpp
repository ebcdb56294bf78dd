#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "fieldlidar/core/pose.hpp"

using namespace fieldlidar;

TEST(Trajectory, InterpolatesTranslationAndYaw) {
  Trajectory t;
  t.push_back(0.0, make_pose(0, 0, 0, 0, 0, 0));
  t.push_back(2.0, make_pose(4, 2, 0, 0, 0, std::numbers::pi / 2));
  const auto mid = t.at(1.0);
  ASSERT_TRUE(mid.has_value());
  EXPECT_NEAR(mid->translation().x(), 2.0, 1e-12);
  EXPECT_NEAR(mid->translation().y(), 1.0, 1e-12);
  EXPECT_NEAR(yaw_of(*mid), std::numbers::pi / 4, 1e-9);
  EXPECT_FALSE(t.at(-0.1).has_value());
  EXPECT_FALSE(t.at(2.1).has_value());
  EXPECT_NEAR(t.path_length_m(), std::sqrt(20.0), 1e-12);
}

TEST(Trajectory, RejectsTimeGoingBackwards) {
  Trajectory t;
  t.push_back(1.0, Pose::Identity());
  EXPECT_THROW(t.push_back(1.0, Pose::Identity()), std::invalid_argument);
  EXPECT_THROW(t.push_back(std::nan(""), Pose::Identity()), std::invalid_argument);
}

TEST(Pose, MakePoseRollPitchYawOrder) {
  const Pose p = make_pose(1, 2, 3, 0.1, -0.2, 0.3);
  const Eigen::Vector3d ea = p.linear().eulerAngles(2, 1, 0);
  EXPECT_NEAR(ea[0], 0.3, 1e-12);
  EXPECT_NEAR(ea[1], -0.2, 1e-12);
  EXPECT_NEAR(ea[2], 0.1, 1e-12);
}
