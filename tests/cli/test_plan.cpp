// End-to-end: fieldlidar plan on a saved nav2 map with a wall: a path round it (CSV, GeoJSON,
// PNG, summary), and the typed failure of a goal in the wall; the same map as the traversability
// command's GeoTIFF layers.

#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "fieldlidar/io/file_util.hpp"
#include "fieldlidar/io/geotiff.hpp"
#include "fieldlidar/io/nav2_map.hpp"
#include "run_cli.hpp"
#include "test_data.hpp"

namespace fieldlidar::test {
namespace {

namespace fs = std::filesystem;

std::string slurp_file(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), {}};
}

// 30 x 20 m of 0.5 m cells, free, with a wall x in [14, 16], y < 14 m: layers traversability
// (0 on the wall) and impassable (1 on the wall).
Grid2D wall_map() {
  GridGeometry g;
  g.resolution_m = 0.5;
  g.width = 60;
  g.height = 40;
  Grid2D grid(g);
  auto tau = grid.add_layer("traversability", 1.0f);
  auto imp = grid.add_layer("impassable", 0.0f);
  for (int iy = 0; iy < 28; ++iy)
    for (int ix = 28; ix < 32; ++ix)
      tau[g.linear_index(ix, iy)] = 0.0f, imp[g.linear_index(ix, iy)] = 1.0f;
  return grid;
}

// The wall map as a nav2 map_server map.
void write_map(const fs::path& dir) {
  const io::Nav2Map m = io::encode_nav2_map(wall_map(), "traversability", "traversability.pgm");
  fs::create_directories(dir);
  io::write_file_atomic(dir / "traversability.pgm", m.pgm, true);
  io::write_file_atomic(dir / "traversability.yaml", m.yaml, true);
}

TEST(CliPlan, PathRoundAWallAndATypedFailure) {
  const auto dir = temp_dir("cli_plan");
  write_map(dir / "map");
  const auto out = dir / "out";
  const auto r = run_cli("plan --map " + quoted(dir / "map") +
                         " --start 5,5,0 --goal 25,5,0 --out " + quoted(out));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* n : {"path.csv", "path_raw.csv", "path.geojson", "plan.png", "summary.json"})
    EXPECT_TRUE(fs::exists(out / n)) << n;
  const auto j = nlohmann::json::parse(slurp_file(out / "summary.json"));
  EXPECT_EQ(j["status"], "success");
  // Round the wall's end at y = 14 m (plus the half width): at least 2 * hypot(10, 9.3) = 27.3 m
  // (29.3 m planned).
  EXPECT_GT(j["length_m"].get<double>(), 27.3);
  EXPECT_LT(j["length_m"].get<double>(), 34.0);
  EXPECT_LE(j["max_curvature_per_m"].get<double>(), 1.0 + 1e-6);
  // hurried past 500 expansions only
  EXPECT_EQ(j["late_weight"].get<bool>(), j["expansions"].get<int>() > 500);
  EXPECT_DOUBLE_EQ(j["heuristic_weight"].get<double>(), 1.2);
  // the thorough search (weight 1, never hurried): more expansions, a path as cheap within 2 %
  const auto best = run_cli("plan --map " + quoted(dir / "map") +
                            " --start 5,5,0 --goal 25,5,0 --weight 1 --late-expansions 0 --out " +
                            quoted(dir / "best"));
  ASSERT_EQ(best.exit_code, 0) << best.output;
  const auto jw = nlohmann::json::parse(slurp_file(dir / "best" / "summary.json"));
  EXPECT_DOUBLE_EQ(jw["heuristic_weight"].get<double>(), 1.0);
  EXPECT_FALSE(jw["late_weight"].get<bool>());
  EXPECT_NEAR(jw["cost"].get<double>(), j["cost"].get<double>(), 0.02 * j["cost"].get<double>());
  EXPECT_GE(jw["expansions"].get<int>(), j["expansions"].get<int>());
  const auto g = nlohmann::json::parse(slurp_file(out / "path.geojson"));
  EXPECT_EQ(g["features"][0]["geometry"]["type"], "LineString");

  const auto bad = run_cli("plan --map " + quoted(dir / "map") +
                           " --start 5,5,0 --goal 15,5,0 --out " + quoted(dir / "out2"));
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.output.find("goal_in_collision"), std::string::npos) << bad.output;
  const auto jb = nlohmann::json::parse(slurp_file(dir / "out2" / "summary.json"));
  EXPECT_EQ(jb["status"], "goal_in_collision");
  EXPECT_FALSE(fs::exists(dir / "out2" / "path.csv"));

  const auto nan = run_cli("plan --map " + quoted(dir / "map") +
                           " --start 5,5 --goal 25,5,0 --out " + quoted(dir / "out3"));
  EXPECT_EQ(nan.exit_code, 1);
  EXPECT_NE(nan.output.find("--start"), std::string::npos) << nan.output;
}

// --robot: the robot YAML's min_turn_radius_m is the plan's R_min (--radius still overrides it),
// and an absurd one is refused naming the field.
// The wall map as GeoTIFF layers (traversability.tif, impassable.tif, a slope layer beside them),
// as the traversability command writes them into DIR/layers: planned alike; a layer that is not
// the traversability, or an impassable layer on other cells, is an error naming the file.
TEST(CliPlan, GeoTiffLayersArePlannedOn) {
  const auto dir = temp_dir("cli_plan_layers");
  Grid2D grid = wall_map();
  grid.add_layer("slope_deg", 2.0f);
  fs::create_directories(dir / "layers");
  for (const char* n : {"traversability", "impassable", "slope_deg"})
    io::write_file_atomic(dir / "layers" / (std::string(n) + ".tif"), io::encode_geotiff(grid, n),
                          true);
  const std::string poses = " --start 5,5,0 --goal 25,5,0 --out ";
  const auto r = run_cli("plan --map " + quoted(dir / "layers") + poses + quoted(dir / "a"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto j = nlohmann::json::parse(slurp_file(dir / "a" / "summary.json"));
  EXPECT_EQ(j["map_format"], "geotiff");
  EXPECT_EQ(j["status"], "success");
  EXPECT_GT(j["length_m"].get<double>(), 27.3);  // round the wall, as on the nav2 map
  EXPECT_LT(j["length_m"].get<double>(), 34.0);

  const auto slope =
      run_cli("plan --map " + quoted(dir / "layers" / "slope_deg.tif") + poses + quoted(dir / "b"));
  EXPECT_EQ(slope.exit_code, 1);
  EXPECT_NE(slope.output.find("holds the layer 'slope_deg', not 'traversability'"),
            std::string::npos)
      << slope.output;

  GridGeometry other = grid.geometry();
  other.width = 30;
  Grid2D small(other);
  small.add_layer("impassable", 0.0f);
  io::write_file_atomic(dir / "layers" / "impassable.tif", io::encode_geotiff(small, "impassable"),
                        true);
  const auto differ = run_cli("plan --map " + quoted(dir / "layers") + poses + quoted(dir / "c"));
  EXPECT_EQ(differ.exit_code, 1);
  EXPECT_NE(differ.output.find("impassable.tif: its cells differ"), std::string::npos)
      << differ.output;
}

TEST(CliPlan, TurningRadiusFromTheRobotYaml) {
  const auto dir = temp_dir("cli_plan_robot");
  write_map(dir / "map");
  io::write_file_atomic(dir / "robot.yaml", std::string("robot:\n  min_turn_radius_m: 2.0\n"),
                        true);
  io::write_file_atomic(dir / "bad.yaml", std::string("min_turn_radius_m: 0.01\n"), true);
  const std::string base =
      "plan --map " + quoted(dir / "map") + " --start 5,5,0 --goal 25,5,0 --out ";
  ASSERT_EQ(run_cli(base + quoted(dir / "a") + " --robot " + quoted(dir / "robot.yaml")).exit_code,
            0);
  const auto a = nlohmann::json::parse(slurp_file(dir / "a" / "summary.json"));
  EXPECT_DOUBLE_EQ(a["min_turn_radius_m"].get<double>(), 2.0);
  EXPECT_LE(a["max_curvature_per_m"].get<double>(), 0.5 + 1e-6);
  ASSERT_EQ(
      run_cli(base + quoted(dir / "b") + " --robot " + quoted(dir / "robot.yaml") + " --radius 1.5")
          .exit_code,
      0);
  const auto b = nlohmann::json::parse(slurp_file(dir / "b" / "summary.json"));
  EXPECT_DOUBLE_EQ(b["min_turn_radius_m"].get<double>(), 1.5);
  const auto bad = run_cli(base + quoted(dir / "c") + " --robot " + quoted(dir / "bad.yaml"));
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.output.find("min_turn_radius_m = 0.01 is absurd"), std::string::npos) << bad.output;
}

}  // namespace
}  // namespace fieldlidar::test
