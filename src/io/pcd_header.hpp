#pragma once
/// \file The header of a PCD file: parsed strictly, with the limits that keep a corrupt header
/// from asking for absurd memory. Internal to io/.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace fieldlidar::io::detail {

struct PcdHeader {
  std::vector<std::string> names;
  std::vector<unsigned> sizes;
  std::vector<char> types;
  std::vector<unsigned> counts;
  std::uint64_t width = 0, height = 0, points = 0;
  bool has_width = false, has_height = false, has_points = false;
  int data_type = -1;  ///< 0 ascii, 1 binary, 2 binary_compressed
  std::size_t data_offset = 0;
  std::uint64_t point_step = 0;
  std::array<double, 7> viewpoint{0, 0, 0, 1, 0, 0, 0};  ///< tx ty tz qw qx qy qz
};

/// Raises fieldlidar::Error "<source>: PCD <what>".
[[noreturn]] void pcd_fail(const std::string& source, const std::string& what);

/// The header at the start of `bytes`; raises fieldlidar::Error naming the defect.
PcdHeader parse_pcd_header(std::span<const std::byte> bytes, const std::string& source);

/// PCL's datatype code for a PCD TYPE letter and SIZE (0 when the pair is not valid).
std::uint8_t pcd_pcl_type(char type, unsigned size);

/// The cloud's origin_m from the VIEWPOINT (the pose of the cloud's frame: p_outer = R p + t):
/// its translation when the rotation is the identity (how the writer stores origin_m), else zero
/// (a rotated frame is not an origin shift).
Eigen::Vector3d pcd_origin(const PcdHeader& h);

}  // namespace fieldlidar::io::detail
