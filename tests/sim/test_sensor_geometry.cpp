// Geometry of the simulated sensor against analytic answers: a plane at a known height, a cylinder
// of known radius, the beam elevations of the presets, column azimuths and firing times.

#include <cmath>
#include <map>
#include <numbers>

#include <gtest/gtest.h>

#include "fieldlidar/sim/lidar_simulator.hpp"
#include "sim_test_util.hpp"

namespace fieldlidar::sim {
namespace {

/// A sensor inside a closed 40 x 40 x 12 m room: every beam returns.
Scene room_scene() {
  Scene s = test::flat_scene(0.0, 30.0);
  s.add_mesh(make_aabb({-20, -20, -0.5}, {20, 20, 12}, make_label(LabelClass::kStructure)));
  return s;
}

TEST(SimSensor, FlatPlaneGivesPointsAtItsHeightWithinTheNoise) {
  const double ground_z = 0.3, sensor_z = 2.0;
  const Scene scene = test::flat_scene(ground_z);
  const auto sensor = SensorModel::vlp16();
  const Pose T = make_pose(1.0, -2.0, sensor_z, 0, 0, 0.7);

  SimConfig exact;
  exact.range_noise_m = 0.0;
  const auto f0 = LidarSimulator(scene, sensor, exact).scan(0.0, T);
  ASSERT_GT(f0.cloud.size(), 7000u);  // the 8 downward rings x 1800 columns, most within range
  for (const auto& p : f0.cloud.points) EXPECT_NEAR(p.z, ground_z - sensor_z, 2e-4);

  // With noise: the range error along each beam is N(0, sigma).
  SimConfig noisy;
  noisy.range_noise_m = 0.03;
  const auto f1 = LidarSimulator(scene, sensor, noisy).scan(0.0, T);
  double sum = 0, sum2 = 0;
  for (const auto& p : f1.cloud.points) {
    const Eigen::Vector3d v(p.x, p.y, p.z);
    const double true_range = (ground_z - sensor_z) / (v.z() / v.norm());
    const double e = v.norm() - true_range;
    sum += e;
    sum2 += e * e;
  }
  const double n = double(f1.cloud.size());
  const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
  EXPECT_LT(std::abs(mean), 4 * 0.03 / std::sqrt(n));
  EXPECT_NEAR(sd, 0.03, 0.003);
  for (const auto l : f1.cloud.labels) EXPECT_EQ(label_class(l), LabelClass::kGround);
}

TEST(SimSensor, CylinderArcsFitTheirTrueRadius) {
  Scene scene = test::flat_scene(0.0);
  const double radius = 0.25;
  const Eigen::Vector2d centre(6.0, 1.5);
  scene.add_mesh(make_cylinder({centre.x(), centre.y(), -0.5}, {centre.x(), centre.y(), 6.0},
                               radius, radius, 512, make_label(LabelClass::kTrunk, 7)));
  SimConfig cfg;
  cfg.range_noise_m = 0.003;
  const auto frame =
      LidarSimulator(scene, SensorModel::hdl64e(), cfg).scan(0.0, make_pose(0, 0, 1.5, 0, 0, 0));
  std::map<int, std::vector<Eigen::Vector2d>> arcs;
  for (std::size_t i = 0; i < frame.cloud.size(); ++i)
    if (frame.cloud.labels[i] == make_label(LabelClass::kTrunk, 7)) {
      const auto& p = frame.cloud.points[i];
      arcs[p.ring].emplace_back(p.x, p.y);
    }
  ASSERT_GT(arcs.size(), 30u);
  int fitted = 0;
  for (const auto& [ring, pts] : arcs) {
    if (pts.size() < 20) continue;
    const auto [c, r] = test::fit_circle(pts);
    EXPECT_NEAR(r, radius, 0.01) << "ring " << ring;
    EXPECT_NEAR((c - centre).norm(), 0.0, 0.01) << "ring " << ring;
    ++fitted;
  }
  EXPECT_GT(fitted, 30);
  // All arcs together pin the radius to the millimetre.
  std::vector<Eigen::Vector2d> all;
  for (const auto& [ring, pts] : arcs) all.insert(all.end(), pts.begin(), pts.end());
  EXPECT_NEAR(test::fit_circle(all).second, radius, 0.002);
}

TEST(SimSensor, BeamElevationsAndAzimuthsMatchThePreset) {
  const Scene scene = room_scene();
  for (const auto& sensor : {SensorModel::vlp16(), SensorModel::hdl64e(), SensorModel::os1_64()}) {
    SimConfig cfg;
    cfg.range_noise_m = 0.0;
    cfg.organized = true;
    cfg.grazing_dropout_cos = 0.0;
    const auto frame =
        LidarSimulator(scene, sensor, cfg).scan(0.0, make_pose(0.3, 0.2, 1.0, 0, 0, 0.3));
    ASSERT_EQ(frame.cloud.size(), sensor.rings() * std::size_t(sensor.columns)) << sensor.name;
    EXPECT_EQ(frame.cloud.height, sensor.rings());
    std::size_t valid = 0;
    for (std::size_t i = 0; i < frame.cloud.size(); ++i) {
      const auto& p = frame.cloud.points[i];
      if (!p.is_valid()) continue;
      ++valid;
      const int ring = static_cast<int>(i / sensor.columns);
      const int col = static_cast<int>(i % sensor.columns);
      ASSERT_EQ(p.ring, ring);
      // Remove the beam-origin offset (Ouster) before measuring the beam's angles.
      const double az_c = column_azimuth_rad(sensor, col);
      const Eigen::Vector3d v =
          Eigen::Vector3d(p.x, p.y, p.z) -
          sensor.beam_origin_offset_m * Eigen::Vector3d(std::cos(az_c), std::sin(az_c), 0);
      EXPECT_NEAR(std::atan2(v.z(), std::hypot(v.x(), v.y())), sensor.beam_altitudes_rad[ring],
                  2e-5);
      EXPECT_NEAR(std::remainder(std::atan2(v.y(), v.x()) - az_c, 2 * std::numbers::pi), 0.0, 2e-5);
      EXPECT_NEAR(p.time, sensor.sweep_period_s() * col / sensor.columns, 1e-6);
    }
    EXPECT_EQ(valid, frame.cloud.size()) << sensor.name << ": every beam hits the room";
  }
}

TEST(SimSensor, TiltingLaserScansPlanesAtThePresetTilts) {
  const Scene scene = room_scene();
  const auto sensor = SensorModel::tilting_2d();
  SimConfig cfg;
  cfg.range_noise_m = 0.0;
  const auto frame = LidarSimulator(scene, sensor, cfg).scan(0.0, make_pose(0, 0, 1.0, 0, 0, 0));
  ASSERT_GT(frame.cloud.size(), sensor.rings() * 1000u);
  for (const auto& p : frame.cloud.points) {
    // Every point of plane k lies in the plane through the lidar's y axis pitched by tilt k.
    const double tilt = sensor.beam_altitudes_rad[p.ring];
    EXPECT_NEAR(p.z * std::cos(tilt) - p.x * std::sin(tilt), 0.0, 2e-4);
    EXPECT_GE(p.time, 0.f);
    EXPECT_LT(p.time, sensor.sweep_period_s());
  }
  EXPECT_EQ(frame.cloud.ring_count(), sensor.rings());
}

TEST(SimSensor, DropoutsMinRangeAndIntensity) {
  const Scene scene = room_scene();
  const auto sensor = SensorModel::vlp16();
  SimConfig cfg;
  cfg.dropout_probability = 0.3;
  const auto frame = LidarSimulator(scene, sensor, cfg).scan(0.0, make_pose(0, 0, 1.0, 0, 0, 0));
  const double kept = double(frame.cloud.size()) / (sensor.rings() * sensor.columns);
  EXPECT_NEAR(kept, 0.7, 0.02);
  for (const auto& p : frame.cloud.points) {
    EXPECT_GE(Eigen::Vector3f(p.x, p.y, p.z).norm(), sensor.min_range_m);
    EXPECT_GE(p.intensity, 0.f);
    EXPECT_LE(p.intensity, 255.f);
  }
  // Intensity falls with the incidence angle: ground returns of the steepest ring (-15 deg,
  // incidence 75 deg from the normal) are dimmer than the wall returns near normal incidence.
  double ground_low = 0, n_low = 0, wall = 0, n_wall = 0;
  for (std::size_t i = 0; i < frame.cloud.size(); ++i) {
    const auto& p = frame.cloud.points[i];
    if (label_class(frame.cloud.labels[i]) == LabelClass::kGround && p.ring == 3)
      ground_low += p.intensity, ++n_low;
    if (label_class(frame.cloud.labels[i]) == LabelClass::kStructure && p.ring == 8)
      wall += p.intensity, ++n_wall;
  }
  ASSERT_GT(n_low, 100);
  ASSERT_GT(n_wall, 100);
  EXPECT_LT(ground_low / n_low, 0.5 * wall / n_wall);
  // Same seed and t0 give the same sweep; another t0 other noise.
  const LidarSimulator sim(scene, sensor, cfg);
  const auto a = sim.scan(1.0, make_pose(0, 0, 1.0, 0, 0, 0));
  const auto b = sim.scan(1.0, make_pose(0, 0, 1.0, 0, 0, 0));
  const auto c = sim.scan(1.1, make_pose(0, 0, 1.0, 0, 0, 0));
  ASSERT_EQ(a.cloud.size(), b.cloud.size());
  EXPECT_EQ(a.cloud.points[100].x, b.cloud.points[100].x);
  EXPECT_NE(a.cloud.size(), c.cloud.size());
}

TEST(SimSensor, MaxRangeCutsFarReturns) {
  auto sensor = SensorModel::vlp16();
  sensor.max_range_m = 8.0;  // the room's walls are 20 m away
  SimConfig cfg;
  cfg.range_noise_m = 0.0;
  const auto frame =
      LidarSimulator(room_scene(), sensor, cfg).scan(0.0, make_pose(0, 0, 1.0, 0, 0, 0));
  ASSERT_GT(frame.cloud.size(), 1000u);
  for (std::size_t i = 0; i < frame.cloud.size(); ++i) {
    EXPECT_LE(frame.cloud.points[i].xyz().norm(), 8.0f);
    EXPECT_EQ(label_class(frame.cloud.labels[i]), LabelClass::kGround);
  }
  // Only beams steeper than atan(1 / 8) reach the ground within 8 m: rings 0..3 (-15..-9 deg).
  EXPECT_EQ(frame.cloud.ring_count(), 4u);
}

TEST(SimSensor, InvalidSensorIsRejected) {
  auto bad = SensorModel::vlp16();
  bad.max_range_m = 0.1;
  EXPECT_THROW(LidarSimulator(room_scene(), bad), std::invalid_argument);
  SimConfig cfg;
  cfg.dropout_probability = 1.5;
  EXPECT_THROW(LidarSimulator(room_scene(), SensorModel::vlp16(), cfg), std::invalid_argument);
  const LidarSimulator sim(room_scene(), SensorModel::vlp16());
  EXPECT_THROW(
      sim.scan(0.0, [](double t) { return make_pose(t > 0.05 ? NAN : 0.0, 0, 1, 0, 0, 0); }),
      std::invalid_argument);
}

}  // namespace
}  // namespace fieldlidar::sim
