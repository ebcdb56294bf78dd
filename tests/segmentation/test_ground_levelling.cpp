// The robust ground on simulated sweeps from a tilted sensor (handheld, on a slope): levelled by
// the estimated ground plane or a measured up direction, it must score as when level.

#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

#include "fieldlidar/segmentation/segment.hpp"
#include "fieldlidar/sim/lidar_simulator.hpp"
#include "fieldlidar/sim/motion.hpp"
#include "fieldlidar/sim/scenes.hpp"

namespace fieldlidar::segmentation {
namespace {

// One frame of the scene's route at t0_s with the sensor rolled (about its x axis) or pitched
// (about its y axis) by tilt_deg on its mount.
struct TiltedFrame {
  PointCloud cloud;
  Eigen::Vector3d up_in_lidar;  ///< the world's up in the lidar frame at the sweep start
};

TiltedFrame tilted_frame(const sim::Scene& scene, const SensorModel& sensor, double t0_s,
                         double tilt_deg, bool pitch) {
  const auto motion = sim::drive_scene_route(scene, t0_s + 1.0);
  const Eigen::AngleAxisd tilt(tilt_deg * std::numbers::pi / 180.0,
                               pitch ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitX());
  const auto pose = [&motion, tilt](double t) {
    Pose T = motion.T_world_lidar(t);
    T.linear() = T.linear() * tilt.toRotationMatrix();
    return T;
  };
  const sim::LidarSimulator lidar(scene, sensor);
  TiltedFrame f;
  f.cloud = lidar.scan(t0_s, pose).cloud;
  f.up_in_lidar = pose(t0_s).linear().transpose() * Eigen::Vector3d::UnitZ();
  return f;
}

GroundScore score(const PointCloud& cloud, const GroundResult& r) {
  const std::vector<std::uint16_t> ground{std::uint16_t(LabelClass::kGround)};
  const std::vector<std::uint16_t> ignored{std::uint16_t(LabelClass::kUnlabelled)};
  return score_ground(cloud, r.is_ground, cloud.labels, ground, ignored);
}

struct Case {
  sim::SceneKind kind;
  const char* sensor;
  double t0_s;
};

class TiltedGround : public ::testing::TestWithParam<Case> {};

TEST_P(TiltedGround, LevelledF1WithinTwoPointsOfTheLevelSensor) {
  const Case c = GetParam();
  const sim::Scene scene = sim::make_scene(c.kind, 7);
  const SensorModel sensor = *SensorModel::preset(c.sensor);
  const GroundConfig plain{};
  GroundConfig off;
  off.levelling.enabled = false;
  const TiltedFrame level = tilted_frame(scene, sensor, c.t0_s, 0.0, false);
  const GroundResult level_r = segment_ground(level.cloud, sensor, plain);
  const double level_f1 = score(level.cloud, level_r).f1;
  EXPECT_FALSE(level_r.levelled) << "estimated tilt " << level_r.tilt_deg;
  std::printf("%s %s level: F1 %.4f (estimated tilt %.1f deg)\n", sim::to_string(c.kind).c_str(),
              c.sensor, level_f1, level_r.tilt_deg);
  for (const bool pitch : {false, true})
    for (const double tilt : {10.0, 20.0, 30.0, 35.0}) {
      const TiltedFrame f = tilted_frame(scene, sensor, c.t0_s, tilt, pitch);
      const GroundResult est = segment_ground(f.cloud, sensor, plain);
      GroundConfig imu;
      imu.levelling.up = f.up_in_lidar;
      const GroundResult measured = segment_ground(f.cloud, sensor, imu);
      const double f1_est = score(f.cloud, est).f1, f1_imu = score(f.cloud, measured).f1;
      const double f1_off = score(f.cloud, segment_ground(f.cloud, sensor, off)).f1;
      const double true_tilt = std::acos(f.up_in_lidar.z()) * 180.0 / std::numbers::pi;
      std::printf(
          "  %s %4.1f deg (true tilt %4.1f, estimated %4.1f): F1 %.4f estimated up, %.4f "
          "measured up, %.4f not levelled\n",
          pitch ? "pitch" : "roll ", tilt, true_tilt, est.tilt_deg, f1_est, f1_imu, f1_off);
      EXPECT_GE(f1_est, level_f1 - 0.02) << (pitch ? "pitch " : "roll ") << tilt;
      EXPECT_GE(f1_imu, level_f1 - 0.02) << (pitch ? "pitch " : "roll ") << tilt;
      EXPECT_NEAR(est.tilt_deg, true_tilt, 4.0);
    }
}

// Measured (estimated up): lawn VLP-16 level 0.9829, tilted 10-35 deg 0.9853-0.9952 (not
// levelled 0.31-0.97); lawn OS1-64 0.9905 -> 0.9904-0.9968 (0.60-0.95); terrain VLP-16 0.9801 ->
// 0.9754-0.9973 (0.06-0.95); terrain OS1-64 0.9678 -> 0.9682-0.9945 (0.07-0.95). Tilted frames
// score higher than level ones: the sensor sees more of the near ground. Not asserted: the forest
// scene rolled 10 deg scores 0.933 (VLP-16) and 0.964 (OS1-64) against 0.981 and 0.992 level,
// with a measured up as with the estimated one (recall 0.90: ground far out on the side looking
// up, where the scan lines thin out); rolled 20-35 deg or pitched it scores 0.971-0.998.
INSTANTIATE_TEST_SUITE_P(Scenes, TiltedGround,
                         ::testing::Values(Case{sim::SceneKind::kLawn, "vlp16", 1.0},
                                           Case{sim::SceneKind::kLawn, "os1-64", 4.0},
                                           Case{sim::SceneKind::kTerrain, "vlp16", 1.0},
                                           Case{sim::SceneKind::kTerrain, "os1-64", 6.0}),
                         [](const auto& info) {
                           std::string s =
                               sim::to_string(info.param.kind) + "_" + info.param.sensor;
                           for (auto& ch : s)
                             if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
                           return s;
                         });

TEST(UpsideDown, TurnedOverSensorIsLevelledAndASteepOneIsSaidSo) {
  // The lawn VLP-16 rolled 180 deg on its mount (hung under a bracket): its ground lies above it
  // in its own frame, found only with the sweep turned over. Rolled 60 deg, no plane within
  // max_tilt_deg is found either way, and the result says so.
  const sim::Scene scene = sim::make_scene(sim::SceneKind::kLawn, 7);
  const SensorModel sensor = SensorModel::vlp16();
  const TiltedFrame level = tilted_frame(scene, sensor, 1.0, 0.0, false);
  const double level_f1 = score(level.cloud, segment_ground(level.cloud, sensor)).f1;
  const TiltedFrame over = tilted_frame(scene, sensor, 1.0, 180.0, false);
  const UpEstimate up = estimate_up(over.cloud);
  ASSERT_TRUE(up.found);
  EXPECT_TRUE(up.upside_down);
  EXPECT_LT(up.up.z(), -0.95);  // up points down the lidar's z axis
  EXPECT_GT(up.up.dot(over.up_in_lidar), std::cos(3.0 * std::numbers::pi / 180.0));
  const GroundResult r = segment_ground(over.cloud, sensor);
  EXPECT_TRUE(r.levelled && r.upside_down && r.up_found);
  const double over_f1 = score(over.cloud, r).f1;
  std::printf("upside down: F1 %.4f (level %.4f), tilt %.1f deg\n", over_f1, level_f1, r.tilt_deg);
  EXPECT_GE(over_f1, level_f1 - 0.02);
  EXPECT_FALSE(estimate_up(level.cloud).upside_down);

  const TiltedFrame steep = tilted_frame(scene, sensor, 1.0, 60.0, false);
  const GroundResult s = segment_ground(steep.cloud, sensor);
  EXPECT_FALSE(s.up_found);
  EXPECT_FALSE(s.levelled);
}

TEST(LevelRotation, TakesUpOntoZAndKeepsTheHeading) {
  // Rolled 180 deg, pitched 20 deg, and turned over with a degree of error: up goes onto z, the
  // lidar's x axis stays ahead (a smallest rotation from nearly 180 deg turns the heading by
  // whatever the error's direction is).
  const auto rot = [](double deg, const Eigen::Vector3d& axis) {
    return Eigen::AngleAxisd(deg * std::numbers::pi / 180.0, axis).toRotationMatrix();
  };
  for (const Eigen::Matrix3d& tilt :
       {rot(180.0, Eigen::Vector3d::UnitX()), rot(20.0, Eigen::Vector3d::UnitY()),
        Eigen::Matrix3d(rot(179.0, Eigen::Vector3d::UnitX()) * rot(0.7, Eigen::Vector3d::UnitY())),
        Eigen::Matrix3d(rot(10.0, Eigen::Vector3d::UnitX()) * rot(-15.0, Eigen::Vector3d::UnitY())),
        rot(90.0, Eigen::Vector3d::UnitY())}) {
    UpEstimate up;
    up.up = tilt.transpose() * Eigen::Vector3d::UnitZ();  // the world's up in the lidar frame
    const Eigen::Matrix3d R = level_rotation(up);
    EXPECT_NEAR((R * up.up - Eigen::Vector3d::UnitZ()).norm(), 0.0, 1e-12);
    EXPECT_NEAR(R.determinant(), 1.0, 1e-12);
    EXPECT_NEAR((R * R.transpose() - Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-12);
    // The lidar's x axis (its y when x points up) laid level points along the levelled x.
    const Eigen::Vector3d ahead =
        std::abs(up.up.x()) < 0.99 ? R * Eigen::Vector3d::UnitX() : R * Eigen::Vector3d::UnitY();
    const double heading = std::abs(up.up.x()) < 0.99 ? std::atan2(ahead.y(), ahead.x())
                                                      : std::atan2(-ahead.x(), ahead.y());
    EXPECT_NEAR(heading, 0.0, 1e-9);
  }
}

}  // namespace
}  // namespace fieldlidar::segmentation
