#pragma once
// Reeds–Shepp shortcutting of a searched path: sub-paths between path poses are replaced by the
// obstacle-free Reeds–Shepp curve joining their ends when it costs less (greedy, the farthest
// end first). The curves run at R_min and every sample of them is checked with the footprint,
// so the path keeps its guarantees; its start and end poses do not move.

#include "fieldlidar/planning/planning_map.hpp"
#include "fieldlidar/planning/pose2.hpp"
#include "path_cost.hpp"

namespace fieldlidar::planning {

struct ShortcutConfig {
  double radius_m = 1.0;          ///< R_min of the curves
  double resolution_m = 0.1;      ///< sample spacing of the curves (as the path's)
  double anchor_spacing_m = 0.5;  ///< path poses tried as curve ends are about this far apart
  double shrink = 0.67;           ///< each failed try moves the far end this much closer
  PathCostTerms cost;
};

struct ShortcutReport {
  int replaced = 0;  ///< sub-paths replaced by a curve
  int tried = 0;     ///< curves computed
  double cost_before = 0.0, cost_after = 0.0;
};

/// Every sample after the first has its footprint free (every 8th is looked at first: a blocked
/// curve is usually blocked over several samples, so it is rejected after few checks).
bool samples_free(const Path& samples, const PlanningMap& map);

/// The path with cheaper obstacle-free Reeds–Shepp curves in place of some of its sub-paths.
Path shortcut_path(const Path& path, const PlanningMap& map, const ShortcutConfig& config,
                   ShortcutReport* report = nullptr);

}  // namespace fieldlidar::planning
