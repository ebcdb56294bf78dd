#include "support/planar_paths.hpp"

#include <cmath>
#include <sstream>

#include <fmt/core.h>

#include "fieldlidar/core/error.hpp"

namespace fieldlidar::app {

planning::Pose2 parse_pose(const std::string& text, const std::string& option) {
  std::string s = text;
  for (char& c : s)
    if (c == ',') c = ' ';
  std::istringstream in(s);
  planning::Pose2 p;
  std::string extra;
  if (!(in >> p.x_m >> p.y_m >> p.yaw_rad) || (in >> extra))
    throw Error(option + ": '" + text + "' is not x,y,yaw (m, m, rad)");
  return p;
}

std::string path_csv(const planning::Path& path) {
  std::string s = "x_m,y_m,yaw_rad,reverse\n";
  for (const auto& p : path)
    s += fmt::format("{:.4f},{:.4f},{:.5f},{}\n", p.pose.x_m, p.pose.y_m, p.pose.yaw_rad,
                     int(p.reverse));
  return s;
}

}  // namespace fieldlidar::app
