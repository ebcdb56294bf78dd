#pragma once
/// \file KITTI tracking labels (`label_02/<sequence>.txt`): one object per line,
/// `frame track_id type truncated occluded alpha bbox(4) h w l x y z ry`, 3D boxes in the
/// rectified camera frame (x right, y down, z forward; (x, y, z) the centre of the box's bottom
/// face, ry the rotation about y). DontCare rows carry no 3D box.

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

namespace fieldlidar::io {

struct KittiObject {
  int frame = 0;
  int track_id = -1;
  std::string type;  ///< Car, Van, Pedestrian, Cyclist, DontCare, ...
  double truncated = 0;
  int occluded = 0;
  double h_m = 0, w_m = 0, l_m = 0;                         ///< box height, width, length
  Eigen::Vector3d bottom_rect_m = Eigen::Vector3d::Zero();  ///< bottom-face centre (rect. camera)
  double ry_rad = 0;

  bool has_box() const { return type != "DontCare" && h_m > 0 && w_m > 0 && l_m > 0; }
  /// True when `p_rect` (rectified camera frame, m) lies in the box grown by `margin_m` on
  /// every side.
  bool contains(const Eigen::Vector3d& p_rect, double margin_m = 0.0) const;
  /// The box centre in the rectified camera frame.
  Eigen::Vector3d center_rect_m() const { return bottom_rect_m - Eigen::Vector3d(0, h_m / 2, 0); }
};

/// Throws fieldlidar::Error naming `source` and the line for a row with fewer than 17 fields, a
/// non-number, a negative frame, or a box size <= 0 on an object other than DontCare.
std::vector<KittiObject> parse_kitti_tracking_labels(std::string_view text,
                                                     const std::string& source);
std::vector<KittiObject> read_kitti_tracking_labels(const std::filesystem::path& path);

}  // namespace fieldlidar::io
