#pragma once
/// \file Files of start/goal pairs for the navigate loop (`fieldlidar navigate --pairs`, the
/// navigate tests' data): one pair per line, "name, sx, sy, syaw, gx, gy, gyaw[, expect]" (m, m,
/// rad; expect "arrived" or "unreachable"), '#' starts a comment.

#include <string>
#include <vector>

#include "fieldlidar/planning/pose2.hpp"

namespace fieldlidar::loops {

struct NavigatePair {
  std::string name;  ///< a folder name (no '/' or '\', not starting with '.')
  planning::Pose2 start, goal;
  std::string expect;  ///< "arrived", "unreachable" or "" (not said)
};

/// The pairs of `file`, in order. Throws fieldlidar::Error naming the file and line on an
/// unreadable file, a line that is not a pair, a bad name or expectation, or a file with no pair.
std::vector<NavigatePair> read_navigate_pairs(const std::string& file);

}  // namespace fieldlidar::loops
