#pragma once
// Planar poses given on the command line and planned paths written as CSV (plan, navigate).

#include <string>

#include "fieldlidar/planning/pose2.hpp"

namespace fieldlidar::app {

/// "x,y,yaw" (m, m, rad); fieldlidar::Error naming `option` otherwise.
planning::Pose2 parse_pose(const std::string& text, const std::string& option);

/// CSV with the header x_m,y_m,yaw_rad,reverse.
std::string path_csv(const planning::Path& path);

}  // namespace fieldlidar::app
