#pragma once
// The files of one navigate run: plans (CSV, GeoJSON), the log, the summary, the picture and the
// map the robot built (nav2 map_server YAML + PGM).

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "fieldlidar/loops/navigate.hpp"

namespace fieldlidar::app {

/// The files a run writes into its folder.
std::vector<std::filesystem::path> navigate_files(const std::filesystem::path& dir);

/// The settings a run drove with, for its summary.json: the robot, the map's cells, the start's
/// and the sensor's options.
nlohmann::json navigate_settings(const loops::NavigateConfig& cfg);

/// summary.json's content (outcome, reason, lengths, ratio, impassable frames, replans, ...).
nlohmann::json navigate_summary(const loops::NavigateResult& r);

/// Writes every file of navigate_files(dir) (the folder exists; check_writable done).
void write_navigate_run(const std::filesystem::path& dir, const loops::NavigateResult& r,
                        const nlohmann::json& extra, const std::string& title, bool force);

}  // namespace fieldlidar::app
