#include "support/sweep_levelling.hpp"

#include <fmt/core.h>

#include "support/warnings.hpp"

namespace fieldlidar::app {

Pose levelling_pose(const PointCloud& cloud, const segmentation::LevellingConfig& config,
                    const std::string& input, nlohmann::json* summary, bool* warned) {
  const segmentation::UpEstimate up = segmentation::estimate_up(cloud, config);
  const bool level = up.found && up.tilt_deg > config.level_tolerance_deg;
  if (summary) {
    (*summary)["tilt_deg"] = up.tilt_deg;
    (*summary)["upside_down"] = up.upside_down;
    (*summary)["levelled"] = level;
  }
  Pose T = Pose::Identity();
  const bool say = !(warned && *warned);
  if (warned && (!up.found || level)) *warned = true;
  if (!up.found && say)
    warn(
        fmt::format("{}: no ground plane below the sensor within {} deg of its z axis, upright "
                    "or turned over: taken as level",
                    input, config.max_tilt_deg));
  if (!level) return T;
  T.linear() = segmentation::level_rotation(up);
  if (say)
    warn(
        fmt::format("{}: the sensor is tilted {:.1f} deg{}: the sweep is levelled to the "
                    "ground plane below it",
                    input, up.tilt_deg, up.upside_down ? " (upside down)" : ""));
  return T;
}

}  // namespace fieldlidar::app
