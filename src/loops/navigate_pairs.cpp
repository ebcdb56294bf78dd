// Files of start/goal pairs for the navigate loop (navigate_pairs.hpp).

#include "fieldlidar/loops/navigate_pairs.hpp"

#include <fstream>
#include <sstream>

#include <fmt/core.h>

#include "fieldlidar/core/error.hpp"

namespace fieldlidar::loops {

namespace {

/// x, y and yaw from three fields (m, m, rad).
planning::Pose2 pose_of(const std::string& x, const std::string& y, const std::string& yaw,
                        const std::string& where) {
  std::istringstream in(x + " " + y + " " + yaw);
  planning::Pose2 p;
  std::string extra;
  if (!(in >> p.x_m >> p.y_m >> p.yaw_rad) || (in >> extra))
    throw Error(where + ": '" + x + "," + y + "," + yaw + "' is not x,y,yaw (m, m, rad)");
  return p;
}

}  // namespace

std::vector<NavigatePair> read_navigate_pairs(const std::string& file) {
  std::ifstream in(file);
  if (!in) throw Error("--pairs " + file + ": cannot read");
  std::vector<NavigatePair> out;
  std::string text;
  for (int n = 1; std::getline(in, text); ++n) {
    if (const auto h = text.find('#'); h != std::string::npos) text.resize(h);
    std::vector<std::string> f;
    std::stringstream ss(text);
    for (std::string cell; std::getline(ss, cell, ',');) {
      const auto a = cell.find_first_not_of(" \t\r"), b = cell.find_last_not_of(" \t\r");
      f.push_back(a == std::string::npos ? "" : cell.substr(a, b - a + 1));
    }
    if (f.empty() || (f.size() == 1 && f[0].empty())) continue;
    const std::string where = fmt::format("--pairs {} line {}", file, n);
    if (f.size() != 7 && f.size() != 8)
      throw Error(where + ": expected name,sx,sy,syaw,gx,gy,gyaw[,expect]");
    NavigatePair p{f[0], pose_of(f[1], f[2], f[3], where + " start"),
                   pose_of(f[4], f[5], f[6], where + " goal"), f.size() == 8 ? f[7] : ""};
    if (p.name.empty() || p.name.find_first_of("/\\") != std::string::npos || p.name[0] == '.')
      throw Error(where + ": '" + p.name + "' is not a folder name");
    if (!p.expect.empty() && p.expect != "arrived" && p.expect != "unreachable")
      throw Error(where + ": expect '" + p.expect + "' is not arrived or unreachable");
    out.push_back(p);
  }
  if (out.empty()) throw Error("--pairs " + file + ": no pair in the file");
  return out;
}

}  // namespace fieldlidar::loops
