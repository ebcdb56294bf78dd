/// The robot's sizes and limits from YAML, checked.
#include "fieldlidar/terrain/robot_config.hpp"

#include <fstream>
#include <sstream>

#include <fmt/core.h>
#include <yaml-cpp/yaml.h>

#include "fieldlidar/core/error.hpp"

namespace fieldlidar::terrain {
namespace {

void check(const std::string& source, const char* field, double v, bool ok, const char* range) {
  if (!ok)
    throw Error(fmt::format("{}: {} = {} is absurd: it must be in {}", source, field, v, range));
}

}  // namespace

void check_robot_config(const RobotConfig& r, const std::string& source) {
  check(source, "length_m", r.length_m, r.length_m > 0 && r.length_m <= 20, "(0, 20] m");
  check(source, "width_m", r.width_m, r.width_m > 0 && r.width_m <= 20, "(0, 20] m");
  check(source, "max_slope_deg", r.max_slope_deg, r.max_slope_deg > 0 && r.max_slope_deg < 80,
        "(0, 80) deg");
  check(source, "max_step_m", r.max_step_m, r.max_step_m > 0 && r.max_step_m <= 5, "(0, 5] m");
  check(source, "clearance_m", r.clearance_m, r.clearance_m > 0 && r.clearance_m <= 20,
        "(0, 20] m");
  check(source, "min_obstacle_height_m", r.min_obstacle_height_m,
        r.min_obstacle_height_m >= 0 && r.min_obstacle_height_m < r.clearance_m,
        "[0, clearance_m)");
  check(source, "min_turn_radius_m", r.min_turn_radius_m,
        r.min_turn_radius_m >= 0.1 && r.min_turn_radius_m <= 100, "[0.1, 100] m");
}

RobotConfig parse_robot_config(std::string_view text, const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(std::string(text));
  } catch (const YAML::Exception& e) {
    throw Error(source + ": not YAML: " + e.what());
  }
  const YAML::Node node = root.IsMap() && root["robot"] ? root["robot"] : root;
  if (!node.IsMap()) throw Error(source + ": expected a map of robot sizes (length_m: 0.93, ...)");
  RobotConfig r;
  const std::pair<const char*, double*> fields[] = {
      {"length_m", &r.length_m},
      {"width_m", &r.width_m},
      {"max_slope_deg", &r.max_slope_deg},
      {"max_step_m", &r.max_step_m},
      {"clearance_m", &r.clearance_m},
      {"min_obstacle_height_m", &r.min_obstacle_height_m},
      {"min_turn_radius_m", &r.min_turn_radius_m}};
  for (const auto& kv : node) {
    const std::string key = kv.first.as<std::string>();
    double* target = nullptr;
    for (const auto& [name, ptr] : fields)
      if (key == name) target = ptr;
    if (!target)
      throw Error(source + ": unknown key '" + key +
                  "' (length_m, width_m, max_slope_deg, max_step_m, clearance_m, "
                  "min_obstacle_height_m, min_turn_radius_m)");
    try {
      *target = kv.second.as<double>();
    } catch (const YAML::Exception&) {
      throw Error(source + ": " + key + " is not a number");
    }
  }
  check_robot_config(r, source);
  return r;
}

RobotConfig load_robot_config(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw Error(path.string() + ": cannot read the robot config");
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_robot_config(ss.str(), path.string());
}

}  // namespace fieldlidar::terrain
