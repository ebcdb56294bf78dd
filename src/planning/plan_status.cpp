// Stable names of the planner's results (files, logs, the CLI).

#include "fieldlidar/planning/hybrid_astar.hpp"

namespace fieldlidar::planning {

const char* to_string(PlanStatus s) {
  switch (s) {
    case PlanStatus::kSuccess:
      return "success";
    case PlanStatus::kInvalidInput:
      return "invalid_input";
    case PlanStatus::kStartOffMap:
      return "start_off_map";
    case PlanStatus::kGoalOffMap:
      return "goal_off_map";
    case PlanStatus::kStartInCollision:
      return "start_in_collision";
    case PlanStatus::kGoalInCollision:
      return "goal_in_collision";
    case PlanStatus::kMapUnknown:
      return "map_unknown";
    case PlanStatus::kNoPath:
      return "no_path";
    case PlanStatus::kTimedOut:
      return "timed_out";
    case PlanStatus::kExpansionLimit:
      return "expansion_limit";
  }
  return "unknown";
}

}  // namespace fieldlidar::planning
