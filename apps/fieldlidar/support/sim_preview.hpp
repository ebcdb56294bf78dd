#pragma once
// The top-down preview picture of `fieldlidar simulate --preview`.

#include <filesystem>
#include <string>
#include <vector>

#include "fieldlidar/core/grid2d.hpp"
#include "fieldlidar/sim/lidar_simulator.hpp"
#include "fieldlidar/sim/motion.hpp"
#include "fieldlidar/sim/scenes.hpp"

namespace fieldlidar::app {

/// Top-down picture: ground elevation, a plan section of the objects (what lies below 2.5 m above
/// the ground) coloured by class, the truth (people, trees, impassable terrain when `terrain` is
/// given) and the robot's path over `frame_times`.
void write_preview(const std::filesystem::path& path, const sim::Scene& scene,
                   const sim::LidarSimulator& simulator, const sim::RobotMotion& motion,
                   const std::vector<double>& frame_times, const Grid2D* terrain,
                   const std::string& title, bool force);

}  // namespace fieldlidar::app
