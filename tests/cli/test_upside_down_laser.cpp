// A 2D laser mounted upside down, placed by its poses (`--odom`) or by its mount (`--mount`):
// its scans come mirrored and clockwise, and `follow --replay` and `legs` mirror them back, so
// the operator is followed and the people found as with the laser upright.

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "csv_text.hpp"
#include "fieldlidar/io/cloud_file.hpp"
#include "fieldlidar/io/trajectory_io.hpp"
#include "run_cli.hpp"
#include "test_data.hpp"

namespace fieldlidar {
namespace {

namespace fs = std::filesystem;

/// The simulator's 2D scans of `sim` as the same laser turned over about its x axis records
/// them (y negated, the beams in reverse order), with its poses turned over alike, into `over`.
void turn_over(const fs::path& sim, const fs::path& over) {
  fs::create_directories(over / "pcd");
  for (const auto& e : fs::directory_iterator(sim / "pcd")) {
    PointCloud c = io::read_cloud(e.path());
    for (auto& p : c.points) p.y = -p.y;
    std::reverse(c.points.begin(), c.points.end());
    io::write_cloud(over / "pcd" / e.path().filename(), c);
  }
  fs::copy_file(sim / "times.txt", over / "times.txt");
  Trajectory turned;
  for (const auto& s : io::read_tum(sim / "poses_tum.txt")) {
    Pose T = s.pose;
    T.linear() = T.linear() * Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();
    turned.push_back(s.stamp_s, T);
  }
  io::write_tum(over / "poses_tum.txt", turned);
}

// The lawn's 2D laser, 300 scans, the operator ahead: turned over, chosen and held as upright,
// at the same place in every scan (before the mirroring: placed mirrored about the laser's
// heading, up to 2.3 m from where the upright laser put them).
TEST(CliUpsideDownLaser, ScansMirroredBackAndTheOperatorFollowedAsUpright) {
  const auto dir = test::temp_dir("cli_upside_down_laser");
  const fs::path sim = dir / "sim", over = dir / "over";
  auto r = test::run_cli("simulate --scene lawn --sensor laser2d --frames 300 --out " +
                         test::quoted(sim));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  turn_over(sim, over);
  std::vector<std::vector<std::vector<std::string>>> logs;
  std::vector<nlohmann::json> summaries;
  for (const fs::path& in : {sim, over}) {
    const fs::path out = dir / (in.filename().string() + "_follow");
    r = test::run_cli("follow --replay " + test::quoted(in) + " --odom " +
                      test::quoted(in / "poses_tum.txt") + " --out " + test::quoted(out));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    logs.push_back(test::csv_text_rows(out / "follow_log.csv"));
    std::ifstream s(out / "summary.json");
    summaries.push_back(nlohmann::json::parse(s));
  }
  const auto& up = summaries[0]["metrics"];
  const auto& down = summaries[1]["metrics"];
  ASSERT_LE(up["frames_before_target_chosen"].get<int>(), 25);
  EXPECT_GE(up["target_held_fraction"].get<double>(), 0.98);
  EXPECT_LE(down["frames_before_target_chosen"].get<int>(),
            up["frames_before_target_chosen"].get<int>() + 2);
  EXPECT_GE(down["target_held_fraction"].get<double>(), 0.98);
  // The held target at the same place (log: t, mower x y yaw, est_x, est_y, ...).
  ASSERT_EQ(logs[0].size(), logs[1].size());
  int both = 0;
  for (std::size_t i = 0; i < logs[0].size(); ++i) {
    if (logs[0][i][4] == "nan" || logs[1][i][4] == "nan") continue;
    ++both;
    const Eigen::Vector2d a(std::stod(logs[0][i][4]), std::stod(logs[0][i][5]));
    const Eigen::Vector2d b(std::stod(logs[1][i][4]), std::stod(logs[1][i][5]));
    EXPECT_LT((a - b).norm(), 0.05) << "scan " << i;
  }
  EXPECT_GE(both, 250);

  // `legs --odom`: the same persons where both report them.
  std::vector<std::size_t> persons;
  for (const fs::path& in : {sim, over}) {
    const fs::path csv = dir / (in.filename().string() + "_legs.csv");
    r = test::run_cli("legs " + test::quoted(in) + " --odom " + test::quoted(in / "poses_tum.txt") +
                      " --out " + test::quoted(csv));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    std::size_t n = 0;
    for (const auto& f : test::csv_text_rows(csv)) n += f.size() > 1 && f[1] == "person";
    persons.push_back(n);
  }
  EXPECT_GE(persons[0], 250u);
  EXPECT_EQ(persons[1], persons[0]);

  // No poses, the mount given instead (`--mount`, roll 180 deg): the robot taken as standing,
  // its motion matched from the scans, and the target where the upright laser puts it.
  std::vector<std::vector<std::vector<std::string>>> still;
  for (const auto& [in, mount] :
       {std::pair{sim, std::string()}, {over, " --mount 0,0,0,180,0,0"}}) {
    const fs::path out = dir / (in.filename().string() + "_still");
    r = test::run_cli("follow --replay " + test::quoted(in) + mount + " --out " +
                      test::quoted(out));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    still.push_back(test::csv_text_rows(out / "follow_log.csv"));
  }
  ASSERT_EQ(still[0].size(), still[1].size());
  int held = 0;
  for (std::size_t i = 0; i < still[0].size(); ++i) {
    EXPECT_EQ(still[0][i][4] == "nan", still[1][i][4] == "nan") << "scan " << i;
    if (still[0][i][4] == "nan" || still[1][i][4] == "nan") continue;
    ++held;
    EXPECT_NEAR(std::stod(still[0][i][4]), std::stod(still[1][i][4]), 1e-3) << "scan " << i;
    EXPECT_NEAR(std::stod(still[0][i][5]), std::stod(still[1][i][5]), 1e-3) << "scan " << i;
  }
  EXPECT_GE(held, 200);
  const auto bad = test::run_cli("follow --replay " + test::quoted(over) +
                                 " --mount 0,0,nan,180,0,0 --out " + test::quoted(dir / "bad"));
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.output.find("--mount"), std::string::npos) << bad.output;
}

}  // namespace
}  // namespace fieldlidar
