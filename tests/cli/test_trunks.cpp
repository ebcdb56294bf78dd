// End-to-end: fieldlidar trunks on a real pine plot (terrestrial scan, no rings).

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "fieldlidar/core/rotate_points.hpp"
#include "fieldlidar/io/cloud_file.hpp"
#include "fieldlidar/io/trajectory_io.hpp"
#include "rotated_copy.hpp"
#include "run_cli.hpp"
#include "test_data.hpp"

namespace fieldlidar::test {
namespace {

std::vector<std::vector<double>> csv_rows(const std::filesystem::path& p, std::string& header) {
  std::ifstream in(p);
  std::getline(in, header);
  std::vector<std::vector<double>> rows;
  for (std::string line; std::getline(in, line);) {
    std::stringstream s(line);
    std::vector<double>& r = rows.emplace_back();
    // An empty cell (dbh_m of a stem whose diameter no scan line measured) reads NaN.
    for (std::string cell; std::getline(s, cell, ',');)
      r.push_back(cell.empty() ? std::nan("") : std::stod(cell));
  }
  return rows;
}

TEST(CliTrunks, PinePlotTreesWithPlausibleDiametersAndNoOverwrite) {
  FIELDLIDAR_REQUIRE_DATA("forest_tls/pine_plot.las");
  const auto dir = temp_dir("cli_trunks");
  const auto out = dir / "trees";
  const std::string cmd = "trunks " + quoted(data_file("forest_tls/pine_plot.las")) + " --out ";
  auto r = run_cli(cmd + quoted(out));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::string header;
  const auto rows = csv_rows(out / "trees.csv", header);
  EXPECT_EQ(header,
            "id,x_m,y_m,z_base_m,dbh_m,axis_x,axis_y,axis_z,height_seen_m,arc_deg,residual_m,"
            "observations,dbh_uncertain");
  // A 10 x 10 m plot of pines: about 16 stems a person would count, DBH 0.1-0.4 m.
  EXPECT_GE(rows.size(), 12u);
  EXPECT_LE(rows.size(), 22u);
  for (const auto& t : rows) {
    ASSERT_EQ(t.size(), 13u);
    EXPECT_GE(t[1], -0.5);  // inside the plot (its own coordinates, 0..10 m)
    EXPECT_LE(t[1], 10.5);
    EXPECT_GE(t[2], -0.5);
    EXPECT_LE(t[2], 10.5);
    EXPECT_GT(t[4], 0.05);
    EXPECT_LT(t[4], 0.6);
    EXPECT_GT(t[7], 0.9);  // upright axes
  }
  std::ifstream g(out / "trees.geojson");
  const auto geo = nlohmann::json::parse(g);
  EXPECT_EQ(geo["type"], "FeatureCollection");
  EXPECT_EQ(geo["features"].size(), rows.size());
  EXPECT_GT(std::filesystem::file_size(out / "trees.png"), 1000u);
  // Nothing is replaced without --force.
  r = run_cli(cmd + quoted(out));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("--force"), std::string::npos) << r.output;
}

// A short simulated forest drive: poses of every scan, the trunk map and its scores; the same
// frames without rings (the KITTI .bin copies) are refused with the frame named.
TEST(CliTrunks, SimulatedDriveTracksPosesAndMapsTrunks) {
  const auto dir = temp_dir("cli_trunks_drive");
  auto r = run_cli("simulate --scene forest --seed 3 --frames 30 --out " + quoted(dir / "sim"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto out = dir / "map";
  r = run_cli("trunks " + quoted(dir / "sim") + " --out " + quoted(out) + " --truth " +
              quoted(dir / "sim" / "trees.csv"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("30 scans (29 tracked on trunks)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("truth: "), std::string::npos) << r.output;
  std::ifstream poses(out / "poses.txt");
  int lines = 0;
  for (std::string l; std::getline(poses, l);) ++lines;
  EXPECT_EQ(lines, 30);
  EXPECT_TRUE(std::filesystem::exists(out / "poses_tum.txt"));
  std::string header;
  const auto rows = csv_rows(out / "trees.csv", header);
  EXPECT_GE(rows.size(), 10u);
  for (const auto& t : rows) EXPECT_GE(t[11], 5.0);  // seen in five scans or more
  EXPECT_GT(std::filesystem::file_size(out / "trees.png"), 1000u);
  // One scan of the drive against the same truth: the truth is moved into the scan's frame with
  // the simulator's pose of that scan (it matched nothing in the world frame) and scored within
  // 15 m of the sensor.
  r = run_cli("trunks " + quoted(dir / "sim" / "pcd" / "000029.pcd") + " --out " +
              quoted(dir / "one") + " --truth " + quoted(dir / "sim" / "trees.csv"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto at = r.output.find("within 15 m of the sensor");
  ASSERT_NE(at, std::string::npos) << r.output;
  double precision = 0, recall = 0;
  ASSERT_EQ(std::sscanf(r.output.c_str() + r.output.find("precision", at),
                        "precision %lf, recall %lf", &precision, &recall),
            2)
      << r.output;
  EXPECT_GE(precision, 0.95) << r.output;
  EXPECT_GE(recall, 0.85) << r.output;
  r = run_cli("trunks " + quoted(dir / "sim" / "velodyne") + " --out " + quoted(dir / "bin"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("frame 0 has no ring field"), std::string::npos) << r.output;
}

/// The "truth: ..." line's DBH RMSE, position RMSE and recall (NaN when absent).
std::array<double, 3> truth_figures(const std::string& output) {
  std::array<double, 3> f{NAN, NAN, NAN};
  const auto at = output.find("truth: ");
  if (at == std::string::npos) return f;
  const std::string line = output.substr(at, output.find('\n', at) - at);
  const auto number_after = [&](const std::string& key) {
    const auto k = line.find(key);
    return k == std::string::npos ? NAN : std::atof(line.c_str() + k + key.size());
  };
  return {number_after("DBH RMSE "), number_after("position RMSE "), number_after("recall ")};
}

// A drive through the forest whose VLP-16 is mounted pitched 15 deg (the sweeps rotated, the
// simulator's poses turned alike): every scan is laid level by the rotation that levels the
// first, and the trunk map is scored as the level drive's. Measured (20 scans): DBH RMSE 5.7 mm,
// position RMSE 14.7 mm, recall 1 (level 4.7 mm, 11.5 mm, 1); before the levelling 24.0 mm and
// 41.6 mm (trunks cut at a slant, the map tilted; on 40 scans recall 0.667 too).
TEST(CliTrunks, TiltedMountSequenceIsLevelledByItsFirstScan) {
  const auto dir = temp_dir("cli_trunks_tilted_drive");
  auto r = run_cli("simulate --scene forest --frames 20 --out " + quoted(dir / "sim"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto tilted = dir / "tilted";
  std::filesystem::create_directories(tilted / "pcd");
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(15.0 * M_PI / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
  for (const auto& e : std::filesystem::directory_iterator(dir / "sim" / "pcd")) {
    write_rotated(e.path(), tilted / "pcd" / e.path().filename(), R.cast<float>());
  }
  std::filesystem::copy_file(dir / "sim" / "times.txt", tilted / "times.txt");
  Trajectory turned;
  for (const auto& s : io::read_kitti_poses(dir / "sim" / "poses.txt")) {
    Pose T = s.pose;
    T.linear() = T.linear() * R.transpose();
    turned.push_back(s.stamp_s, T);
  }
  io::write_kitti_poses(tilted / "poses.txt", turned);
  const std::string truth = " --truth " + quoted(dir / "sim" / "trees.csv");
  r = run_cli("trunks " + quoted(dir / "sim") + " --out " + quoted(dir / "level_map") + truth);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto level = truth_figures(r.output);
  r = run_cli("trunks " + quoted(tilted) + " --out " + quoted(dir / "tilted_map") + truth);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("is tilted"), std::string::npos) << r.output;
  const auto pitched = truth_figures(r.output);
  EXPECT_LE(level[0], 0.01) << r.output;
  EXPECT_LE(pitched[0], 0.012) << r.output;
  EXPECT_LE(pitched[1], 0.025) << r.output;
  EXPECT_GE(pitched[2], level[2]) << r.output;
}

}  // namespace
}  // namespace fieldlidar::test

namespace fieldlidar::test {
namespace {

// TreeLS's dbh.las, a 0.1 m slice of one stem with a branch running off it: one stem, its
// diameter from the circle the branch does not widen (0.288 m; a least-squares circle through
// every point reads 0.866 m).
// A real under-canopy sweep (forest_sloam, OS1-64) from a sensor pitched 25 deg or mounted
// upside down is levelled by the ground plane below it before its trunks are looked for, with a
// warning: about as many trees as the level sweep gives (33 and 30 measured; 9 when pitched
// before the levelling), most within 0.5 m of the level sweep's.
TEST(CliTrunks, TiltedSweepIsLevelledBeforeItsTrunks) {
  const std::string name = "forest_sloam/moving_ground_t0.pcd";
  FIELDLIDAR_REQUIRE_DATA(name);
  const auto dir = temp_dir("cli_trunks_tilted");
  const PointCloud level = io::read_cloud(data_file(name));
  std::string header;
  const auto trees_of = [&](const std::string& tag, const Eigen::Matrix3f& R) {
    PointCloud c = level;
    rotate_points(c, R);
    io::write_cloud(dir / (tag + ".pcd"), c);
    const auto r =
        run_cli("trunks " + quoted(dir / (tag + ".pcd")) + " --out " + quoted(dir / tag));
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(r.output.find("is tilted") != std::string::npos, tag != "level") << r.output;
    return csv_rows(dir / tag / "trees.csv", header);
  };
  const auto flat = trees_of("level", Eigen::Matrix3f::Identity());
  ASSERT_GE(flat.size(), 25u);  // 33 measured
  const Eigen::Matrix3f pitch =
      Eigen::AngleAxisf(float(25.0 * M_PI / 180.0), Eigen::Vector3f::UnitY()).toRotationMatrix();
  const auto pitched = trees_of("pitched", pitch);
  EXPECT_GE(pitched.size(), flat.size() - 3);
  // In the levelled frame the pitched sweep's trees stand where the level one's do: 26 of 33
  // within 0.5 m measured (median 0.17 m; the others are trees only one of the two found).
  std::size_t near = 0;
  for (const auto& t : pitched)
    for (const auto& f : flat)
      if (std::hypot(t[1] - f[1], t[2] - f[2]) < 0.5) {
        ++near;
        break;
      }
  EXPECT_GE(10 * near, 7 * pitched.size());
  const auto over = trees_of(
      "upside_down", Eigen::AngleAxisf(float(M_PI), Eigen::Vector3f::UnitX()).toRotationMatrix());
  EXPECT_GE(over.size(), flat.size() - 5);
}

TEST(CliTrunks, StemSliceGivesTheStemsDiameter) {
  FIELDLIDAR_REQUIRE_DATA("forest_tls/dbh.las");
  const auto out = temp_dir("cli_trunks_slice") / "slice";
  const auto r =
      run_cli("trunks " + quoted(data_file("forest_tls/dbh.las")) + " --out " + quoted(out));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("a stem slice"), std::string::npos) << r.output;
  std::string header;
  const auto rows = csv_rows(out / "trees.csv", header);
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_NEAR(rows[0][4], 0.288, 0.01);
  EXPECT_NEAR(rows[0][1], 101.45, 0.02);  // the file's own coordinates
  EXPECT_NEAR(rows[0][2], 152.02, 0.02);
  EXPECT_GT(rows[0][9], 300.0);  // arc seen, deg
}

// --truth is read and checked before anything is written, whatever the input: a missing file, a
// value that is not a finite number, a DBH that is not positive and a file with no tree are
// errors naming the file (and line and column), with no output folder left behind.
TEST(CliTrunks, TruthIsCheckedBeforeAnyOutput) {
  const auto dir = temp_dir("cli_trunks_truth");
  const auto scan = dir / "one.bin";
  {
    const float point[4] = {1, 2, 0.5f, 0};
    std::ofstream(scan, std::ios::binary).write(reinterpret_cast<const char*>(point), 16);
  }
  const std::string header = "id,base_x_m,base_y_m,base_z_m,axis_x,axis_y,axis_z,dbh_m,height_m\n";
  std::ofstream(dir / "header.csv") << header;
  std::ofstream(dir / "neg.csv") << header << "1,3,4,0,0,0,1,-1,12\n";
  std::ofstream(dir / "nan.csv") << header << "1,3,4,0,0,0,1,0.3,12\n2,nan,4,0,0,0,1,0.3,12\n";
  std::ofstream(dir / "flat.csv") << header << "1,3,4,0,1,0,0,0.3,12\n";
  const struct {
    std::string truth, message;
  } cases[] = {
      {"missing.csv", "missing.csv"},
      {"header.csv", "header.csv: holds no tree"},
      {"neg.csv", "neg.csv: line 2: dbh_m -1 is not a positive diameter"},
      {"nan.csv", "nan.csv: line 3: base_x_m is nan, not a finite number"},
      {"flat.csv", "flat.csv: line 2: axis (1, 0, 0) does not point up"},
  };
  for (const auto& c : cases) {
    const auto out = dir / "out";
    const auto r = run_cli("trunks " + quoted(scan) + " --truth " + quoted(dir / c.truth) +
                           " --out " + quoted(out));
    EXPECT_EQ(r.exit_code, 1) << c.truth << "\n" << r.output;
    EXPECT_NE(r.output.find("fieldlidar: error: "), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(c.message), std::string::npos) << c.truth << "\n" << r.output;
    EXPECT_FALSE(std::filesystem::exists(out)) << c.truth;
  }
}

// A stem slice is scored against --truth too, in the file's own coordinates.
TEST(CliTrunks, StemSliceIsScoredAgainstTheTruth) {
  FIELDLIDAR_REQUIRE_DATA("forest_tls/dbh.las");
  const auto dir = temp_dir("cli_trunks_slice_truth");
  std::ofstream(dir / "truth.csv") << "id,base_x_m,base_y_m,base_z_m,axis_x,axis_y,axis_z,dbh_m\n"
                                   << "1,101.45,152.02,0,0,0,1,0.29\n";
  const auto r = run_cli("trunks " + quoted(data_file("forest_tls/dbh.las")) + " --truth " +
                         quoted(dir / "truth.csv") + " --out " + quoted(dir / "slice"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("truth: 1 trees, 1 detected, 1 matched"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace fieldlidar::test
