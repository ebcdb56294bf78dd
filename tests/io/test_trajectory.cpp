#include <cmath>
#include <fstream>

#include <gtest/gtest.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/trajectory_io.hpp"
#include "test_data.hpp"

using namespace fieldlidar;

namespace {
Trajectory spiral() {
  Trajectory t;
  for (int i = 0; i < 40; ++i)
    t.push_back(1600000000.0 + 0.1 * i, make_pose(2.0 * std::cos(0.1 * i), 2.0 * std::sin(0.1 * i),
                                                  0.01 * i, 0.02 * i, -0.01 * i, 0.1 * i + 1.0));
  return t;
}
void expect_same(const Trajectory& a, const Trajectory& b, bool times) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (times) {
      EXPECT_NEAR(a[i].stamp_s, b[i].stamp_s, 1e-6);
    }
    EXPECT_LT((a[i].pose.matrix() - b[i].pose.matrix()).cwiseAbs().maxCoeff(), 1e-9);
  }
}
}  // namespace

TEST(Trajectory, KittiRoundTripWithTimes) {
  const auto traj = spiral();
  const auto dir = test::temp_dir("traj_kitti");
  io::write_kitti_poses(dir / "poses.txt", traj);
  io::write_kitti_times(dir / "times.txt", traj);
  expect_same(io::read_kitti_poses(dir / "poses.txt", dir / "times.txt"), traj, true);
  const auto no_times = io::read_kitti_poses(dir / "poses.txt");
  expect_same(no_times, traj, false);
  EXPECT_DOUBLE_EQ(no_times[3].stamp_s, 3.0);  // line index when there is no times file
  EXPECT_THROW(io::write_kitti_poses(dir / "poses.txt", traj), Error);
}

TEST(Trajectory, TumRoundTrip) {
  const auto traj = spiral();
  const auto dir = test::temp_dir("traj_tum");
  io::write_tum(dir / "t.tum", traj);
  expect_same(io::read_tum(dir / "t.tum"), traj, true);
}

TEST(Trajectory, MalformedTextNamesFileAndLine) {
  auto expect_error = [](auto parse, std::string text, const char* needle) {
    try {
      parse(text);
      FAIL() << "accepted: " << text;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  auto kitti = [](const std::string& s) { return io::parse_kitti_poses(s, "p.txt"); };
  auto tum = [](const std::string& s) { return io::parse_tum(s, "t.txt"); };
  expect_error(kitti, "1 0 0 0 0 1 0 0 0 0 1\n", "p.txt:1");  // 11 numbers
  expect_error(kitti, "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 nan 0 0 1 0\n", "p.txt:2");
  expect_error(kitti, "2 0 0 0 0 1 0 0 0 0 1 0\n", "not a rotation");
  expect_error(kitti, "1 0 0 0 0 1 0 0 0 0 1 zero\n", "not a number");
  expect_error(tum, "0 1 2 3 0 0 0 0\n", "zero length");
  expect_error(tum, "1 0 0 0 0 0 0 1\n0.5 0 0 0 0 0 0 1\n", "t.txt:2");  // time goes back
  expect_error(tum, "1 0 0 0 0 0 1\n", "expected 8");
  EXPECT_THROW(io::parse_kitti_poses("1 0 0 0 0 1 0 0 0 0 1 0\n", "p.txt", {0.0, 1.0}), Error);
  EXPECT_TRUE(io::parse_tum("# only a comment\n\n", "t.txt").empty());
}

TEST(Trajectory, RealKittiGroundTruth) {
  FIELDLIDAR_REQUIRE_DATA("kitti00/poses.txt");
  const auto traj = io::read_kitti_poses(test::data_file("kitti00/poses.txt"),
                                         test::data_file("kitti00/times.txt"));
  ASSERT_EQ(traj.size(), 6u);
  EXPECT_DOUBLE_EQ(traj[0].stamp_s, 0.0);
  EXPECT_DOUBLE_EQ(traj[5].stamp_s, 0.5184302);  // last line of times.txt (~10.4 Hz)
  EXPECT_TRUE(traj[0].pose.isApprox(Pose::Identity(), 1e-5));
  // The car drives forward (camera z) a few metres in half a second.
  EXPECT_GT(traj[5].pose.translation().z(), 2.0);
  EXPECT_LT(traj.path_length_m(), 10.0);
}
