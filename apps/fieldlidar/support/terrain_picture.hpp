#pragma once
// The traversability map as one top-down PNG of four panels: where the robot can go (tau,
// impassable, unknown), slope, roughness, and why cells block (steep, step, obstacle).

#include <filesystem>
#include <string>

#include "fieldlidar/core/grid2d.hpp"
#include "fieldlidar/terrain/traversability.hpp"

namespace fieldlidar::app {

void draw_terrain_map(const Grid2D& map, const terrain::RobotConfig& robot,
                      const std::string& title, const std::filesystem::path& path, bool force);

}  // namespace fieldlidar::app
