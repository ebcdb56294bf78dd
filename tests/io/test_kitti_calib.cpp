#include <cmath>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/core/trajectory_metrics.hpp"
#include "fieldlidar/io/kitti_calib.hpp"
#include "fieldlidar/io/trajectory_io.hpp"
#include "test_data.hpp"

using namespace fieldlidar;

TEST(KittiCalib, ConjugatesCameraPosesIntoTheLidarFrame) {
  // C = R0_rect * Tr_velo_to_cam with R0_rect a small rotation; a LiDAR trajectory taken to the
  // camera frame (C T C^-1) comes back.
  const Pose r0 = make_pose(0, 0, 0, 0.01, -0.004, 0.007);
  const Pose tr = make_pose(0.1, -0.2, -0.3, -std::numbers::pi / 2, 0.0, -std::numbers::pi / 2);
  std::string text = "P2: 1 0 0 0 0 1 0 0 0 0 1 0\nR0_rect:";
  for (int k = 0; k < 9; ++k) text += " " + std::to_string(r0.linear()(k / 3, k % 3));
  text += "\nTr_velo_to_cam:";
  for (int k = 0; k < 12; ++k) text += " " + std::to_string(tr.matrix()(k / 4, k % 4));
  text += "\n";
  const io::KittiCalib calib = io::parse_kitti_calib(text, "calib");
  EXPECT_LT((calib.T_rect_velo.matrix() - (r0 * tr).matrix()).cwiseAbs().maxCoeff(), 1e-5);
  Trajectory lidar, camera;
  for (int i = 0; i < 5; ++i) {
    const Pose p = make_pose(i, 0.1 * i, 0, 0, 0, 0.05 * i);
    lidar.push_back(i, p);
    camera.push_back(i, calib.T_rect_velo * p * calib.T_rect_velo.inverse(Eigen::Isometry));
  }
  const Trajectory back = io::camera_to_lidar(camera, calib);
  for (int i = 0; i < 5; ++i)
    EXPECT_LT((back[i].pose.matrix() - lidar[i].pose.matrix()).cwiseAbs().maxCoeff(), 1e-12);
  // The odometry layout: `Tr` alone.
  const io::KittiCalib odo = io::parse_kitti_calib(
      "P0: 1 0 0 0 0 1 0 0 0 0 1 0\nTr: 0 -1 0 0 0 0 -1 0 1 0 0 0\n", "calib_odo");
  EXPECT_LT((odo.T_rect_velo.linear() * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitZ()).norm(),
            1e-12);  // LiDAR forward is camera forward
}

TEST(KittiCalib, BadFilesNameTheProblem) {
  EXPECT_THROW(io::parse_kitti_calib("P2: 1 2 3\n", "c"), Error);
  EXPECT_THROW(io::parse_kitti_calib("Tr_velo_to_cam: 1 0 0\n", "c"), Error);
  EXPECT_THROW(io::parse_kitti_calib("Tr: 1 0 0 0 0 1 0 0 0 0 1 x\n", "c"), Error);
  EXPECT_THROW(io::parse_kitti_calib("Tr: 2 0 0 0 0 1 0 0 0 0 1 0\n", "c"), Error);
  EXPECT_THROW(io::read_kitti_calib("/nonexistent/calib.txt"), Error);
  try {
    io::parse_kitti_calib("R0_rect: 1 0 0\n", "my_calib.txt");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("my_calib.txt:1 (R0_rect)"), std::string::npos)
        << e.what();
  }
}

TEST(KittiCalib, OrbSlamReferenceOfTrackingSequence0000InTheLidarFrame) {
  FIELDLIDAR_REQUIRE_DATA("kitti_tracking0000/calib.txt");
  const auto dir = test::data_file("kitti_tracking0000");
  const io::KittiCalib calib = io::read_kitti_calib(dir / "calib.txt");
  const Trajectory camera = io::read_kitti_poses(dir / "orbslam3_poses_0000_frames0-49.txt");
  const Trajectory lidar = io::camera_to_lidar(camera, calib);
  ASSERT_EQ(lidar.size(), 50u);
  const Pose last = lidar[49].pose;
  // The car drives forward (LiDAR +x) about 18 m on a level road and turns about 38 degrees
  // about the LiDAR's up axis.
  EXPECT_GT(last.translation().x(), 12.0);
  EXPECT_LT(std::abs(last.translation().z()), 0.5);
  EXPECT_NEAR(lidar.path_length_m(), 18.0, 1.5);
  const double turn_deg = rotation_angle_rad(last.linear()) * 180.0 / std::numbers::pi;
  EXPECT_NEAR(turn_deg, 38.0, 4.0);
  EXPECT_GT(std::abs(last.linear()(2, 2)),
            std::cos(5.0 * std::numbers::pi / 180.0));  // up stays up
}
