#pragma once
// Start/goal pairs of the navigate tests (data/navigate_pairs_terrain_seed*.csv): one pair per
// line, name,sx,sy,syaw,gx,gy,gyaw,expect (m, rad; expect arrived or unreachable); '#' comments.

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "fieldlidar/planning/hybrid_astar.hpp"

namespace fieldlidar::loops::test {

struct Pair {
  std::string name, expect;
  planning::Pose2 start, goal;
};

inline std::vector<Pair> read_pairs(const std::string& file) {
  std::ifstream in(file);
  std::vector<Pair> out;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    for (char& c : line)
      if (c == ',') c = ' ';
    std::istringstream ss(line);
    Pair p;
    ss >> p.name >> p.start.x_m >> p.start.y_m >> p.start.yaw_rad >> p.goal.x_m >> p.goal.y_m >>
        p.goal.yaw_rad >> p.expect;
    if (ss) out.push_back(p);
  }
  return out;
}

}  // namespace fieldlidar::loops::test
