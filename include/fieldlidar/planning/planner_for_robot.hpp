#pragma once
/// \file The planner's settings for a given robot: its minimum turning radius comes from the
/// robot config (the robot YAML's min_turn_radius_m), like its footprint.

#include "fieldlidar/planning/hybrid_astar.hpp"
#include "fieldlidar/terrain/traversability.hpp"

namespace fieldlidar::planning {

/// `config` with the robot's R_min (robot.min_turn_radius_m).
inline PlannerConfig planner_config_for(const terrain::RobotConfig& robot,
                                        PlannerConfig config = {}) {
  config.min_turn_radius_m = robot.min_turn_radius_m;
  return config;
}

}  // namespace fieldlidar::planning
