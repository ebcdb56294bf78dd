// End-to-end: fieldlidar traversability on a simulated terrain frame and an airborne survey.

#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <sstream>
#include <string>
#include <tuple>

#include <gtest/gtest.h>
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "fieldlidar/core/rotate_points.hpp"
#include "fieldlidar/io/cloud_file.hpp"
#include "rotated_copy.hpp"
#include "run_cli.hpp"
#include "test_data.hpp"

namespace fieldlidar::test {
namespace {

namespace fs = std::filesystem;

std::string args(std::initializer_list<std::string> words) {
  std::ostringstream s;
  for (const auto& w : words) s << w << ' ';
  return s.str();
}

std::string slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), {}};
}

struct PgmCounts {
  int width = 0, height = 0;
  std::size_t occupied = 0, free = 0, unknown = 0, other = 0;
};

// Reads the P5 image written by the command (one comment line after the magic).
PgmCounts read_pgm(const fs::path& p) {
  std::istringstream s(slurp(p));
  std::string magic, comment;
  PgmCounts c;
  int maxval = 0;
  std::getline(s, magic);
  EXPECT_EQ(magic, "P5");
  std::getline(s, comment);
  EXPECT_EQ(comment.rfind("#", 0), 0u);
  s >> c.width >> c.height >> maxval;
  EXPECT_EQ(maxval, 255);
  s.get();
  const std::string pixels{std::istreambuf_iterator<char>(s), {}};
  EXPECT_EQ(pixels.size(), std::size_t(c.width) * std::size_t(c.height));
  for (unsigned char v : pixels) {
    if (v == 0)
      ++c.occupied;
    else if (v == 254)
      ++c.free;
    else if (v == 205)
      ++c.unknown;
    else
      ++c.other;
  }
  return c;
}

// The checks both inputs share: files, YAML fields, PGM size against the summary, some of each
// class (at least `min_free` free cells). Returns the summary.
nlohmann::json check_outputs(const fs::path& dir, std::size_t min_free = 100) {
  for (const char* n :
       {"traversability.yaml", "traversability.pgm", "traversability.png", "summary.json"})
    EXPECT_TRUE(fs::exists(dir / n)) << n;
  const auto j = nlohmann::json::parse(slurp(dir / "summary.json"));
  const std::string yaml = slurp(dir / "traversability.yaml");
  EXPECT_NE(yaml.find("image: traversability.pgm\n"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("mode: trinary\n"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("negate: 0\n"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("occupied_thresh: 0.65\n"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("free_thresh: 0.196\n"), std::string::npos) << yaml;
  std::ostringstream res;
  res << "resolution: " << j["resolution_m"].get<double>() << "\n";
  EXPECT_NE(yaml.find(res.str()), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("origin: ["), std::string::npos) << yaml;
  const PgmCounts c = read_pgm(dir / "traversability.pgm");
  EXPECT_EQ(c.width, j["width_cells"].get<int>());
  EXPECT_EQ(c.height, j["height_cells"].get<int>());
  EXPECT_EQ(c.other, 0u);  // trinary: three values only
  EXPECT_EQ(c.occupied + c.free, j["cells_known"].get<std::size_t>());
  EXPECT_GT(c.occupied, 10u);
  EXPECT_GT(c.free, min_free);
  EXPECT_GT(c.unknown, 0u);
  EXPECT_GT(fs::file_size(dir / "traversability.png"), 1000u);
  return j;
}

TEST(CliTraversability, SimulatedTerrainFrameAndRefusesToOverwrite) {
  const auto dir = temp_dir("cli_traversability_sim");
  const auto sim = dir / "sim", out = dir / "out";
  const auto s =
      run_cli(args({"simulate", "--scene", "terrain", "--frames", "1", "--out", quoted(sim)}));
  ASSERT_EQ(s.exit_code, 0) << s.output;
  const auto frame = sim / "pcd" / "000000.pcd";
  ASSERT_TRUE(fs::exists(frame));
  const auto r = run_cli(args({"traversability", quoted(frame), "--out", quoted(out)}));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto j = check_outputs(out);
  EXPECT_EQ(j["input"], "sweep");
  EXPECT_EQ(j["sensor"], "vlp16");
  EXPECT_DOUBLE_EQ(j["resolution_m"].get<double>(), 0.5);
  // Seed 0, frame 0 (VLP-16, 40 m reach): 710 of 161 x 161 cells known, 92 impassable.
  EXPECT_GT(j["cells_known"].get<int>(), 500);
  EXPECT_GT(j["cells_impassable"].get<int>(), 30);
  EXPECT_GT(j["cells_passable"].get<int>(), 300);
  // The map is a square of 2 * 40 m around the sensor: origin at (-40, -40).
  EXPECT_NE(slurp(out / "traversability.yaml").find("origin: [-40, -40, 0.0]"), std::string::npos);
  // Outputs exist: without --force nothing is replaced, with it all is.
  const auto before = slurp(out / "summary.json");
  const auto again = run_cli(args({"traversability", quoted(frame), "--out", quoted(out)}));
  EXPECT_EQ(again.exit_code, 1);
  EXPECT_NE(again.output.find("already exists"), std::string::npos) << again.output;
  EXPECT_EQ(slurp(out / "summary.json"), before);
  EXPECT_EQ(
      run_cli(args({"traversability", quoted(frame), "--out", quoted(out), "--force"})).exit_code,
      0);
  EXPECT_EQ(run_cli(args({"traversability", quoted(frame), "--out", quoted(out), "--force",
                          "--cell", "0"}))
                .exit_code,
            1);
  EXPECT_EQ(
      run_cli(args({"traversability", quoted(dir / "missing.pcd"), "--out", quoted(dir / "o2")}))
          .exit_code,
      1);
}

// A sweep from a sensor mounted pitched 30 deg, or upside down, is mapped level (the rotation
// that takes the ground plane's up to z), said in a warning and the summary: its map is the
// level sweep's. Laid in the sensor's own frame, as before, the pitched sweep's map held 28
// passable cells against the level one's 196, and the upside-down one laid its ground 1.2 m
// above the sensor.
TEST(CliTraversability, TiltedOrUpsideDownSensorIsMappedLevel) {
  const auto dir = temp_dir("cli_traversability_tilt");
  const auto sim = dir / "sim";
  ASSERT_EQ(run_cli(args({"simulate", "--scene", "terrain", "--frames", "1", "--out", quoted(sim)}))
                .exit_code,
            0);
  const PointCloud level = io::read_cloud(sim / "pcd" / "000000.pcd");
  const auto map_of = [&](const std::string& name, const Eigen::Matrix3f& R) {
    PointCloud c = level;
    rotate_points(c, R);
    io::write_cloud(dir / (name + ".pcd"), c);
    const auto r = run_cli(args({"traversability", quoted(dir / (name + ".pcd")), "--sensor",
                                 "vlp16", "--out", quoted(dir / name)}));
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return std::pair(nlohmann::json::parse(slurp(dir / name / "summary.json")), r.output);
  };
  const auto [flat, flat_out] = map_of("level", Eigen::Matrix3f::Identity());
  EXPECT_EQ(flat["levelled"], false);
  EXPECT_EQ(flat_out.find("is tilted"), std::string::npos) << flat_out;
  const Eigen::Matrix3f pitch =
      Eigen::AngleAxisf(float(30.0 * M_PI / 180.0), Eigen::Vector3f::UnitY()).toRotationMatrix();
  const Eigen::Matrix3f over =
      Eigen::AngleAxisf(float(M_PI), Eigen::Vector3f::UnitX()).toRotationMatrix();
  for (const auto& [name, R, upside] :
       {std::tuple{"pitched", pitch, false}, std::tuple{"upside_down", over, true}}) {
    const auto [j, out] = map_of(name, R);
    EXPECT_EQ(j["levelled"], true) << name;
    EXPECT_EQ(j["upside_down"], upside) << name;
    EXPECT_NEAR(j["tilt_deg"].get<double>(), upside ? 180.0 : 30.0, 2.0) << name;
    EXPECT_NE(out.find("is tilted"), std::string::npos) << out;
    for (const char* k : {"cells_known", "cells_passable", "cells_impassable"})
      EXPECT_NEAR(j[k].get<double>(), flat[k].get<double>(), 0.15 * flat[k].get<double>())
          << name << " " << k;
  }
}

TEST(CliTraversability, SequenceFusedWithPosesRobotConfigAndGeoTiffs) {
  const auto dir = temp_dir("cli_traversability_seq");
  const auto sim = dir / "sim", out = dir / "out";
  const auto s =
      run_cli(args({"simulate", "--scene", "terrain", "--frames", "20", "--out", quoted(sim)}));
  ASSERT_EQ(s.exit_code, 0) << s.output;
  {
    std::ofstream robot(dir / "robot.yaml");
    robot << "robot:\n  length_m: 1.0\n  width_m: 0.6\n  max_slope_deg: 20\n"
             "  min_turn_radius_m: 1.5\n";
  }
  const auto r = run_cli(args({"traversability", quoted(sim), "--poses", quoted(sim / "poses.txt"),
                               "--robot", quoted(dir / "robot.yaml"), "--out", quoted(out)}));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto j = check_outputs(out);
  EXPECT_EQ(j["input"], "sequence");
  EXPECT_EQ(j["frames"], 20);
  // Every sweep but the last (its end pose unknown) de-skewed by the per-point times.
  EXPECT_EQ(j["frames_deskewed"], 19);
  EXPECT_DOUBLE_EQ(j["robot"]["max_slope_deg"].get<double>(), 20.0);
  EXPECT_DOUBLE_EQ(j["robot"]["min_turn_radius_m"].get<double>(), 1.5);
  EXPECT_GT(j["cells_known"].get<int>(), 500);  // 727 measured (2 s of driving)
  for (const char* layer : {"slope_deg", "roughness_m", "impassable", "traversability",
                            "elevation_m", "obstacle_2d", "step_m", "points"}) {
    const auto tif = out / "layers" / (std::string(layer) + ".tif");
    ASSERT_TRUE(fs::exists(tif)) << tif;
    EXPECT_EQ(slurp(tif).substr(0, 4), std::string("II*\0", 4)) << tif;
  }
  // Without --poses the lidar odometry places the frames (the first scan's frame).
  const auto o = run_cli(args({"traversability", quoted(sim), "--out", quoted(dir / "odo")}));
  ASSERT_EQ(o.exit_code, 0) << o.output;
  const auto jo = nlohmann::json::parse(slurp(dir / "odo" / "summary.json"));
  EXPECT_EQ(jo["frames"], 20);
  EXPECT_NE(jo["placed_by"].get<std::string>().find("odometry"), std::string::npos);
  EXPECT_GT(jo["cells_known"].get<int>(), 500);
  // The same sweeps from a VLP-16 pitched 15 deg: the odometry's map is laid level by the
  // rotation that levels the first scan. Measured: 320 passable and 453 impassable cells
  // against the level sensor's 337 and 422 (297 and 510 in the tilted frame; the levelling takes
  // the ground's plane under the first scan, not the gravity the level sensor has).
  fs::create_directories(dir / "pitched" / "pcd");
  const Eigen::Matrix3f R =
      Eigen::AngleAxisf(float(15.0 * M_PI / 180.0), Eigen::Vector3f::UnitY()).toRotationMatrix();
  for (const auto& e : fs::directory_iterator(sim / "pcd")) {
    write_rotated(e.path(), dir / "pitched" / "pcd" / e.path().filename(), R);
  }
  fs::copy_file(sim / "times.txt", dir / "pitched" / "times.txt");
  const auto p = run_cli(
      args({"traversability", quoted(dir / "pitched"), "--out", quoted(dir / "pitched_map")}));
  ASSERT_EQ(p.exit_code, 0) << p.output;
  EXPECT_NE(p.output.find("is tilted"), std::string::npos) << p.output;
  const auto jp = nlohmann::json::parse(slurp(dir / "pitched_map" / "summary.json"));
  EXPECT_NE(jp["placed_by"].get<std::string>().find("laid level"), std::string::npos);
  const double passable = jo["cells_passable"].get<double>();
  const double impassable = jo["cells_impassable"].get<double>();
  EXPECT_GE(jp["cells_passable"].get<double>(), 0.92 * passable);
  EXPECT_LE(jp["cells_impassable"].get<double>(), 1.12 * impassable);
  // An absurd robot is refused before any work, naming the field.
  {
    std::ofstream robot(dir / "absurd.yaml");
    robot << "width_m: 300\n";
  }
  const auto bad = run_cli(args({"traversability", quoted(sim), "--robot",
                                 quoted(dir / "absurd.yaml"), "--out", quoted(dir / "o3")}));
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.output.find("width_m = 300 is absurd"), std::string::npos) << bad.output;
}

TEST(CliTraversability, AirborneSurveyIsMappedAsAnArea) {
  FIELDLIDAR_REQUIRE_DATA("terrain_als/Topography.las");
  const auto dir = temp_dir("cli_traversability_als");
  const auto r = run_cli(args(
      {"traversability", quoted(data_file("terrain_als/Topography.las")), "--out", quoted(dir)}));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("not one sensor sweep"), std::string::npos) << r.output;
  const auto j = check_outputs(dir, 30);
  EXPECT_EQ(j["input"], "survey");
  // 73,403 returns over 286 x 286 m (0.9 per m2): 3 m cells, 96 x 96. Through the fused cells:
  // 1006 known (10.9 %), 73 passable; the lake's 3897 class-9 returns make it impassable (the
  // single-pass area map had 1563 known, 505 passable, most of them on the lake).
  EXPECT_DOUBLE_EQ(j["resolution_m"].get<double>(), 3.0);
  EXPECT_GT(j["coverage"].get<double>(), 0.09);
  EXPECT_EQ(j["water_points"].get<int>(), 3897);
  EXPECT_LT(j["cells_passable"].get<int>(), 150);
  // The map is in the file's coordinates (LAS origin 273000, 5274000 added).
  EXPECT_NEAR(j["origin_m"][0].get<double>(), 273357.1, 1.0);
  EXPECT_NEAR(j["origin_m"][1].get<double>(), 5274357.1, 1.0);
}

// A real sweep from a vehicle whose body the sensor sees (RELLIS-3D: 15k returns labelled void
// within 2.2 m): they block the cells under the vehicle, so no plan can start there, until
// --min-range drops them. A survey has no sensor to measure ranges from: refused.
TEST(CliTraversability, MinRangeDropsTheVehiclesOwnBody) {
  FIELDLIDAR_REQUIRE_DATA("rellis3d/000001.bin");
  const auto dir = temp_dir("cli_traversability_min_range");
  const std::string scan = quoted(data_file("rellis3d/000001.bin"));
  for (const char* range : {"0", "2.3"}) {
    const fs::path out = dir / (std::string("range_") + range);
    const auto r = run_cli(args({"traversability", scan, "--sensor", "os1-64", "--min-range", range,
                                 "--out", quoted(out)}));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const auto j = check_outputs(out);
    EXPECT_DOUBLE_EQ(j["min_range_m"].get<double>(), std::stod(range));
    const auto plan = run_cli(args({"plan", "--map", quoted(out / "layers"), "--start", "0,0,0",
                                    "--goal", "24,0,0", "--out", quoted(dir / "plan"), "--force"}));
    if (std::string(range) == "0") {
      EXPECT_NE(plan.exit_code, 0) << plan.output;
      EXPECT_NE(plan.output.find("start_in_collision"), std::string::npos) << plan.output;
    } else {
      EXPECT_EQ(plan.exit_code, 0) << plan.output;
    }
  }
  const auto survey =
      run_cli(args({"traversability", quoted(data_file("terrain_als/Topography.las")),
                    "--min-range", "2", "--out", quoted(dir / "survey")}));
  EXPECT_NE(survey.exit_code, 0);
  EXPECT_NE(survey.output.find("--min-range"), std::string::npos) << survey.output;
  EXPECT_FALSE(fs::exists(dir / "survey" / "summary.json"));
}

}  // namespace
}  // namespace fieldlidar::test
