#pragma once
// The picture of a follow replay: where the mower went and where it saw its target, coloured by
// what the follow state was in each scan, with a timeline of the states under it.

#include <filesystem>
#include <span>
#include <string>

#include "fieldlidar/loops/closed_loop.hpp"

namespace fieldlidar::app {

/// Writes a top-down PNG of a replay's log rows (their frame: the recording's odometry frame or
/// the sensor frame): the mower's path, the target estimate per scan coloured by the follow state,
/// and a timeline strip, one column per scan, with the recording's breaks (scans more than
/// `gap_s` apart) marked. Refuses to replace an existing file unless `overwrite`.
void write_follow_replay_picture(const std::filesystem::path& path,
                                 std::span<const loops::LogRow> rows, double gap_s,
                                 const std::string& title, bool overwrite);

}  // namespace fieldlidar::app
