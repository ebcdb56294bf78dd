// The robot config YAML: defaults, the robot: block or a bare map, and clear errors on absurd or
// unknown values.
#include <string>

#include <gtest/gtest.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/terrain/robot_config.hpp"

using namespace fieldlidar;
using namespace fieldlidar::terrain;

namespace {

std::string error_of(const std::string& yaml) {
  try {
    parse_robot_config(yaml, "robot.yaml");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(RobotConfigYaml, ReadsTheBlockOrABareMap) {
  const RobotConfig r =
      parse_robot_config("robot:\n  length_m: 1.2\n  width_m: 0.8\n  max_slope_deg: 20\n", "r");
  EXPECT_DOUBLE_EQ(r.length_m, 1.2);
  EXPECT_DOUBLE_EQ(r.width_m, 0.8);
  EXPECT_DOUBLE_EQ(r.max_slope_deg, 20.0);
  EXPECT_DOUBLE_EQ(r.max_step_m, RobotConfig{}.max_step_m);  // left out: default
  const RobotConfig b = parse_robot_config("max_step_m: 0.3\nclearance_m: 0.9\n", "r");
  EXPECT_DOUBLE_EQ(b.max_step_m, 0.3);
  EXPECT_DOUBLE_EQ(b.clearance_m, 0.9);
  EXPECT_DOUBLE_EQ(b.min_turn_radius_m, 1.0);  // the seed chassis' R_min
  EXPECT_DOUBLE_EQ(parse_robot_config("min_turn_radius_m: 2.5", "r").min_turn_radius_m, 2.5);
}

TEST(RobotConfigYaml, AbsurdOrUnknownValuesAreClearErrors) {
  EXPECT_NE(error_of("length_m: -1").find("robot.yaml: length_m = -1 is absurd"),
            std::string::npos);
  EXPECT_NE(error_of("width_m: 500").find("width_m = 500"), std::string::npos);
  EXPECT_NE(error_of("max_slope_deg: 95").find("max_slope_deg = 95"), std::string::npos);
  EXPECT_NE(error_of("max_step_m: 0").find("max_step_m = 0"), std::string::npos);
  EXPECT_NE(error_of("clearance_m: 0.1\nmin_obstacle_height_m: 0.15")
                .find("min_obstacle_height_m = 0.15"),
            std::string::npos);
  EXPECT_NE(error_of("min_turn_radius_m: 0").find("min_turn_radius_m = 0 is absurd"),
            std::string::npos);
  EXPECT_NE(error_of("min_turn_radius_m: 500").find("min_turn_radius_m = 500"), std::string::npos);
  EXPECT_NE(error_of("min_turn_radius_m: .nan").find("min_turn_radius_m = nan"), std::string::npos);
  EXPECT_NE(error_of("lenght_m: 1").find("unknown key 'lenght_m'"), std::string::npos);
  EXPECT_NE(error_of("length_m: big").find("length_m is not a number"), std::string::npos);
  EXPECT_NE(error_of("[1, 2").find("not YAML"), std::string::npos);
  EXPECT_NE(error_of("- 1\n- 2\n").find("expected a map"), std::string::npos);
  EXPECT_THROW(load_robot_config("/nonexistent/robot.yaml"), Error);
}
