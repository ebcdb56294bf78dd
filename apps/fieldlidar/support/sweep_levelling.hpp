#pragma once
// One sweep laid level before it is mapped: a sensor mounted tilted, or upside down.

#include <string>

#include <nlohmann/json.hpp>

#include "fieldlidar/core/point_cloud.hpp"
#include "fieldlidar/core/pose.hpp"
#include "fieldlidar/segmentation/ground.hpp"

namespace fieldlidar::app {

/// The pose that lays one sweep level: segmentation::level_rotation of the up direction of the
/// ground plane below the sensor (segmentation::estimate_up) when the sensor is tilted past the
/// levelling's tolerance, identity otherwise or when no ground plane is found (both said on
/// stderr, naming `input`); `summary`, when given, gets tilt_deg, upside_down and levelled. The
/// ground segmentation levels for itself, but a map laid in the tilted frame is not level (an
/// upside-down sweep mapped its ground 1.2 m above the sensor), nor are its trunks upright.
/// `warned`, when given, says once per stream: set after the first warning, none after it.
Pose levelling_pose(const PointCloud& cloud, const segmentation::LevellingConfig& config,
                    const std::string& input, nlohmann::json* summary = nullptr,
                    bool* warned = nullptr);

}  // namespace fieldlidar::app
