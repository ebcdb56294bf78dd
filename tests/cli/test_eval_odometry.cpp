// fieldlidar eval-odometry: figures of known answers, KITTI and TUM matching, the KITTI camera
// reference taken to the LiDAR frame, and refusals of bad input.

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "fieldlidar/io/kitti_calib.hpp"
#include "fieldlidar/io/trajectory_io.hpp"
#include "run_cli.hpp"
#include "test_data.hpp"

namespace fieldlidar {
namespace {

namespace fs = std::filesystem;

/// 10 Hz, 0.5 m per frame along a curve.
Trajectory curve(std::size_t n, double scale = 1.0, double time_offset_s = 0.0) {
  Trajectory t;
  for (std::size_t i = 0; i < n; ++i) {
    const double s = 0.5 * static_cast<double>(i);
    t.push_back(100.0 + 0.1 * static_cast<double>(i) + time_offset_s,
                make_pose(scale * 20.0 * std::sin(s / 20.0),
                          scale * 20.0 * (1.0 - std::cos(s / 20.0)), 0.0, 0.0, 0.0, s / 20.0));
  }
  return t;
}

nlohmann::json run_json(const std::string& args) {
  const auto r = test::run_cli("eval-odometry --json " + args);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  try {
    return nlohmann::json::parse(r.output);
  } catch (const std::exception&) {
    ADD_FAILURE() << "not JSON: " << r.output;
    return {};
  }
}

TEST(CliEvalOdometry, KittiRowsOfAShortEstimate) {
  const auto dir = test::temp_dir("eval_odometry_kitti");
  io::write_kitti_poses(dir / "ref.txt", curve(120));
  io::write_kitti_poses(dir / "est.txt", curve(120, 0.98));
  const auto args = test::quoted(dir / "est.txt") + " " + test::quoted(dir / "ref.txt");
  const auto text = test::run_cli("eval-odometry " + args);
  ASSERT_EQ(text.exit_code, 0) << text.output;
  // 59.5 m of path: segments of 5, 10, ..., 40 m, printed.
  EXPECT_NE(text.output.find("5, 10, 15, 20, 25, 30, 35, 40 m"), std::string::npos) << text.output;
  EXPECT_NE(text.output.find("matched by row"), std::string::npos);
  const auto j = run_json(args);
  EXPECT_EQ(j.value("poses", 0), 120);
  EXPECT_NEAR(j["path_length_m"].value("reference", 0.0), 59.5, 0.01);
  EXPECT_NEAR(j["kitti"].value("translation_pct", 0.0), 2.0, 0.1);  // 2 % short, of the chord
  EXPECT_LT(j["kitti"].value("rotation_deg_per_m", 1.0), 1e-9);
  EXPECT_NEAR(j["ate"].value("sim3_scale", 0.0), 1.0 / 0.98, 1e-6);
  EXPECT_LT(j["ate"]["sim3"].value("rmse", 1.0), 1e-6);
  EXPECT_GT(j["ate"]["se3"].value("rmse", 0.0), 0.05);
  EXPECT_NEAR(j["rpe"]["translation_m"].value("mean", 0.0), 0.01, 1e-4);  // 2 % of 0.5 m
  // Given lengths, and an estimate of every 2nd frame against every 2nd reference row.
  const auto j5 = run_json(args + " --lengths 5,10");
  EXPECT_EQ(j5["kitti"]["lengths_m"].size(), 2u);
  Trajectory every_2nd;
  const Trajectory est = curve(120, 0.98);
  for (std::size_t i = 0; i < est.size(); i += 2) every_2nd.push_back(est[i].stamp_s, est[i].pose);
  io::write_kitti_poses(dir / "est2.txt", every_2nd);
  const auto j2 = run_json(test::quoted(dir / "est2.txt") + " " + test::quoted(dir / "ref.txt") +
                           " --ref-stride 2");
  EXPECT_EQ(j2.value("poses", 0), 60);
  EXPECT_NEAR(j2["rpe"]["translation_m"].value("mean", 0.0), 0.02, 2e-4);
}

TEST(CliEvalOdometry, TumFilesAreMatchedByTime) {
  const auto dir = test::temp_dir("eval_odometry_tum");
  io::write_tum(dir / "ref.tum", curve(100));
  // The estimate's clock is 3 ms late and its 10th pose is missing.
  const Trajectory full = curve(100, 1.0, 0.003);
  Trajectory est;
  for (std::size_t i = 0; i < full.size(); ++i)
    if (i != 10) est.push_back(full[i].stamp_s, full[i].pose);
  io::write_tum(dir / "est.tum", est);
  const auto args = test::quoted(dir / "est.tum") + " " + test::quoted(dir / "ref.tum");
  const auto j = run_json(args);
  EXPECT_EQ(j.value("poses", 0), 99);
  EXPECT_NE(j.value("matched", std::string()).find("by time"), std::string::npos);
  EXPECT_LT(j["ate"]["se3"].value("rmse", 1.0), 1e-6);
  const auto tight = test::run_cli("eval-odometry " + args + " --max-dt 0.001");
  EXPECT_EQ(tight.exit_code, 1);
  EXPECT_NE(tight.output.find("--max-dt"), std::string::npos) << tight.output;
}

TEST(CliEvalOdometry, RefusesBadInput) {
  const auto dir = test::temp_dir("eval_odometry_bad");
  io::write_kitti_poses(dir / "ref.txt", curve(50));
  io::write_kitti_poses(dir / "short.txt", curve(49));
  {
    std::ofstream nan(dir / "nan.txt");
    nan << "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 nan 0 1 0 0 0 0 1 0\n";
    std::ofstream odd(dir / "odd.txt");
    odd << "1 2 3 4 5\n";
  }
  const auto ref = " " + test::quoted(dir / "ref.txt");
  const struct {
    std::string args, message;
  } cases[] = {
      {test::quoted(dir / "short.txt") + ref, "has 49 poses"},
      {test::quoted(dir / "nan.txt") + ref, "nan.txt:2"},
      {test::quoted(dir / "odd.txt") + ref, "neither KITTI (12) nor TUM (8)"},
      {test::quoted(dir / "missing.txt") + ref, "missing.txt"},
      {test::quoted(dir / "short.txt") + ref + " --calib " + test::quoted(dir / "short.txt"),
       "no Tr_velo_to_cam"},
      {test::quoted(dir / "ref.txt") + ref + " --lengths 5,-1", "--lengths"},
  };
  for (const auto& c : cases) {
    const auto r = test::run_cli("eval-odometry " + c.args);
    EXPECT_NE(r.exit_code, 0) << c.args;
    EXPECT_NE(r.output.find(c.message), std::string::npos) << c.args << "\n" << r.output;
  }
}

// Figures that would read as a result but score nothing: an RPE without a pair (rmse 0), poses
// so far out that the sums overflow (inf, NaN, a Sim(3) scale of 0), a NaN time gate that
// pairs every pose. Each is an error naming what to change; range errors read as ranges.
TEST(CliEvalOdometry, RefusesPairlessRpeOverflowingPosesAndBadGates) {
  const auto dir = test::temp_dir("eval_odometry_scoreless");
  io::write_kitti_poses(dir / "ref.txt", curve(50));
  Trajectory huge;
  for (std::size_t i = 0; i < 50; ++i)
    huge.push_back(0.1 * double(i), make_pose(1e300 * double(i), 0, 0, 0, 0, 0));
  io::write_kitti_poses(dir / "huge.txt", huge);
  io::write_tum(dir / "ref.tum", curve(50));
  const auto ref = " " + test::quoted(dir / "ref.txt");
  const auto tum = test::quoted(dir / "ref.tum") + " " + test::quoted(dir / "ref.tum");
  const struct {
    std::string args, message;
  } cases[] = {
      {test::quoted(dir / "ref.txt") + ref + " --delta 1000",
       "--delta 1000: no RPE pair in 50 poses"},
      {test::quoted(dir / "ref.txt") + ref + " --delta 50 --json",
       "--delta 50: no RPE pair in 50 poses"},
      {test::quoted(dir / "huge.txt") + ref, "estimate pose 1: translation 1e+300 m is beyond"},
      {tum + " --max-dt nan", "--max-dt: must be a number >= 0, got 'nan'"},
      {tum + " --max-dt -1", "--max-dt: must be >= 0, got -1"},
  };
  for (const auto& c : cases) {
    const auto r = test::run_cli("eval-odometry " + c.args);
    EXPECT_EQ(r.exit_code, 1) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.message), std::string::npos) << c.args << "\n" << r.output;
    EXPECT_LT(r.output.size(), 400u) << r.output;  // no 309-digit DBL_MAX
  }
  // One pair short of the end still scores.
  const auto j = run_json(test::quoted(dir / "ref.txt") + ref + " --delta 49");
  EXPECT_EQ(j["rpe"]["translation_m"].value("count", 0), 1);
}

TEST(CliEvalOdometry, KittiCameraReferenceInTheLidarFrame) {
  FIELDLIDAR_REQUIRE_DATA("kitti_tracking0000/orbslam3_poses_0000_frames0-49.txt");
  const auto data = test::data_file("kitti_tracking0000");
  const auto dir = test::temp_dir("eval_odometry_calib");
  // A LiDAR-frame estimate: the reference itself taken to the LiDAR frame.
  const Trajectory lidar =
      io::camera_to_lidar(io::read_kitti_poses(data / "orbslam3_poses_0000_frames0-49.txt"),
                          io::read_kitti_calib(data / "calib.txt"));
  io::write_kitti_poses(dir / "lidar.txt", lidar);
  const auto args = test::quoted(dir / "lidar.txt") + " " +
                    test::quoted(data / "orbslam3_poses_0000_frames0-49.txt");
  const auto j = run_json(args + " --calib " + test::quoted(data / "calib.txt"));
  EXPECT_EQ(j.value("poses", 0), 50);
  EXPECT_LT(j["kitti"].value("translation_pct", 1.0), 1e-6);
  EXPECT_LT(j["rpe"]["rotation_deg"].value("max", 1.0), 1e-6);
  EXPECT_LT(j["ate"]["se3"].value("rmse", 1.0), 1e-6);
  // Without the calibration the camera-frame reference does not fit a LiDAR-frame estimate.
  const auto raw = run_json(args);
  EXPECT_GT(raw["rpe"]["translation_m"].value("mean", 0.0), 0.1);
}

}  // namespace
}  // namespace fieldlidar
