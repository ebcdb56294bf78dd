#pragma once
/// \file The robot a map is made for, read from YAML (`--robot config.yaml`), shared by the
/// traversability map and the planner.
///
///     robot:                      # the block may also be the whole file
///       length_m: 0.93            # chassis length (m), (0, 20]
///       width_m: 0.58             # chassis width (m), (0, 20]
///       max_slope_deg: 25         # rho_max, (0, 80)
///       max_step_m: 0.20          # h_max, (0, 5]
///       clearance_m: 1.2          # (0, 20], above min_obstacle_height_m
///       min_obstacle_height_m: 0.15  # [0, clearance_m)
///       min_turn_radius_m: 1.0    # R_min of the planner, [0.1, 100]
///
/// Keys left out keep RobotConfig's defaults (the seed's chassis).

#include <filesystem>
#include <string>
#include <string_view>

#include "fieldlidar/terrain/traversability.hpp"

namespace fieldlidar::terrain {

/// Raises fieldlidar::Error naming `source`, the field and its value when a size or limit is
/// absurd (ranges above).
void check_robot_config(const RobotConfig& robot, const std::string& source = "robot config");

/// Parses YAML text; raises fieldlidar::Error naming `source` on bad YAML, an unknown key, a
/// value that is not a number, or an absurd value.
RobotConfig parse_robot_config(std::string_view yaml_text, const std::string& source);
RobotConfig load_robot_config(const std::filesystem::path& path);

}  // namespace fieldlidar::terrain
