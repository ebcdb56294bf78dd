#pragma once
/// \file KITTI calibration files: the LiDAR-to-camera transform, to bring camera-frame reference
/// trajectories (KITTI ground truth, visual SLAM) into the LiDAR frame.
///
/// Two layouts are read: the object/tracking one (`R0_rect:` 9 numbers, `Tr_velo_to_cam:` 12,
/// also spelled `R_rect`/`Tr_velo_cam` without colons) and the odometry one (`Tr:` 12 numbers,
/// already to the rectified camera 0). Other keys (`P0`..`P3`, `Tr_imu_to_velo`) are ignored.

#include <filesystem>
#include <string>
#include <string_view>

#include "fieldlidar/core/pose.hpp"

namespace fieldlidar::io {

struct KittiCalib {
  /// C: maps LiDAR points into the rectified camera frame, R0_rect * Tr_velo_to_cam (or `Tr`).
  /// Its rotation is re-projected onto SO(3) (the file's 7 digits are not exactly orthonormal).
  Pose T_rect_velo = Pose::Identity();
};

/// Throws fieldlidar::Error naming `source` and the line for a key with the wrong number count or
/// a non-number, and when neither `Tr_velo_to_cam` nor `Tr` is present.
KittiCalib parse_kitti_calib(std::string_view text, const std::string& source);
KittiCalib read_kitti_calib(const std::filesystem::path& path);

/// A camera-frame trajectory (T_cam0_cam) as the LiDAR's: T_velo0_velo = C^-1 * T_cam0_cam * C.
Trajectory camera_to_lidar(const Trajectory& camera, const KittiCalib& calib);

}  // namespace fieldlidar::io
