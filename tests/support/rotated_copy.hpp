#pragma once
// A LiDAR file written again turned about its sensor's origin: the sweeps of a sensor mounted
// tilted or upside down, made from a level one's.

#include <filesystem>

#include <Eigen/Core>

#include "fieldlidar/core/rotate_points.hpp"
#include "fieldlidar/io/cloud_file.hpp"

namespace fieldlidar::test {

/// Reads `from`, turns its points by `R` (p <- R p) and writes them to `to` (format by extension).
inline void write_rotated(const std::filesystem::path& from, const std::filesystem::path& to,
                          const Eigen::Matrix3f& R) {
  PointCloud c = io::read_cloud(from);
  rotate_points(c, R);
  io::write_cloud(to, c);
}

}  // namespace fieldlidar::test
