// Walking people in the lawn scene: gait, truth and what the sensor sees of them.

#include <cmath>

#include <gtest/gtest.h>

#include "fieldlidar/sim/lidar_simulator.hpp"
#include "fieldlidar/sim/motion.hpp"
#include "fieldlidar/sim/scenes.hpp"

namespace fieldlidar::sim {
namespace {

TEST(SimPeople, OperatorWalksTheClosedOutlineAtTheSetSpeed) {
  const Scene scene = make_lawn_scene({}, 1);
  const auto& path = scene.operator_path();
  ASSERT_GT(path.size(), 10u);
  // Straight near edge with right-angle corners at both ends.
  const Eigen::Vector2d e0 = (path[1] - path[0]).normalized(),
                        e1 = (path[2] - path[1]).normalized();
  EXPECT_NEAR(e0.dot(e1), 0.0, 1e-9);
  const auto a = scene.people_at(10.0), b = scene.people_at(11.0);
  ASSERT_EQ(a.size(), 1u);
  EXPECT_NEAR(a[0].velocity_m_s.norm(), 1.0, 1e-9);
  EXPECT_NEAR(b[0].path_length_m - a[0].path_length_m, 1.0, 1e-9);
  EXPECT_LT((b[0].position_m - a[0].position_m).norm(), 1.0 + 1e-9);
  // Legs swing: their separation along the walking direction changes over a stride.
  double min_sep = 1e9, max_sep = 0;
  for (double t = 10.0; t < 12.0; t += 0.05) {
    const auto p = scene.people_at(t)[0];
    const double sep = (p.legs_m[0] - p.legs_m[1]).norm();
    min_sep = std::min(min_sep, sep);
    max_sep = std::max(max_sep, sep);
    EXPECT_LT((0.5 * (p.legs_m[0] + p.legs_m[1]) - p.position_m).norm(), 0.2);
  }
  EXPECT_LT(min_sep, 0.25);
  EXPECT_GT(max_sep, 0.35);
}

TEST(SimPeople, ScenarioOptions) {
  LawnConfig cfg;
  cfg.operator_stops = true;
  cfg.operator_too_fast = true;
  cfg.fast_time_s = 20.0;
  cfg.second_person_crossing = true;
  cfg.operator_behind_shed = true;
  const Scene scene = make_lawn_scene(cfg, 4);
  ASSERT_EQ(scene.walkers().size(), 2u);
  const auto stop_a = scene.people_at(cfg.stop_time_s + 1)[0],
             stop_b = scene.people_at(cfg.stop_time_s + 4)[0];
  EXPECT_EQ(stop_a.position_m, stop_b.position_m);
  EXPECT_EQ(stop_a.velocity_m_s.norm(), 0.0);
  // Standing still, both feet are under the hips.
  EXPECT_NEAR((stop_a.legs_m[0] - stop_a.legs_m[1]).norm(), 0.2, 1e-6);
  EXPECT_NEAR(scene.people_at(cfg.fast_time_s + 1)[0].velocity_m_s.norm(), cfg.fast_speed_m_s,
              1e-9);
  // The crosser passes 2 m ahead of the operator at the crossing time.
  const auto at = scene.people_at(cfg.crossing_time_s);
  EXPECT_NEAR((at[1].position_m - at[0].position_m).norm(), 2.0, 1e-6);
  EXPECT_GT(at[1].velocity_m_s.norm(), 1.0);
  // ... and stays on the lawn (never walks through the hedge or the shed).
  for (const auto& p : scene.walkers()[1].config().path_m) {
    EXPECT_GE(p.x(), 0.0);
    EXPECT_LE(p.x(), cfg.length_m);
    EXPECT_GE(p.y(), 0.0);
    EXPECT_LE(p.y(), cfg.width_m + 3.0);
  }
  // The detour goes round the far side of the shed (beyond the lawn's right edge).
  double max_x = 0;
  for (const auto& p : scene.operator_path()) max_x = std::max(max_x, p.x());
  EXPECT_GT(max_x, cfg.length_m + 4.5);
}

TEST(SimPeople, SensorSeesLegsWhereTheTruthPutsThem) {
  const Scene scene = make_lawn_scene({}, 2);
  const auto motion = follow_operator(scene, 1, 12.0);
  const LidarSimulator sim(scene, SensorModel::vlp16());
  const double t0 = 10.0;
  const auto frame = sim.scan(t0, motion.lidar_pose_fn());
  ASSERT_EQ(frame.people.size(), 1u);
  EXPECT_FALSE(frame.people[0].visible_from_sensor_unknown);
  EXPECT_GT(frame.people[0].points, 60u);
  std::uint32_t leg_points = 0, counted = 0;
  for (std::size_t i = 0; i < frame.cloud.size(); ++i) {
    if (frame.cloud.labels[i] != make_label(LabelClass::kPerson, 1)) continue;
    ++counted;
    const auto& p = frame.cloud.points[i];
    const double t = t0 + p.time;
    const Eigen::Vector3d w = motion.T_world_lidar(t) * Eigen::Vector3d(p.x, p.y, p.z);
    const double above = w.z() - scene.ground_height_at(w.head<2>());
    if (above < 0.3 || above > 0.6) continue;
    // At knee height a return is on one of the two legs (radius 6.5 cm, axis slanted by the gait).
    const auto truth = scene.people_at(t)[0];
    const double d =
        std::min((w.head<2>() - truth.legs_m[0]).norm(), (w.head<2>() - truth.legs_m[1]).norm());
    EXPECT_LT(d, 0.15);
    ++leg_points;
  }
  EXPECT_EQ(counted, frame.people[0].points);
  EXPECT_GT(leg_points, 10u);
  // Without people, the same sweep has no person label.
  SimConfig no_people;
  no_people.simulate_people = false;
  const auto empty =
      LidarSimulator(scene, SensorModel::vlp16(), no_people).scan(t0, motion.lidar_pose_fn());
  for (auto l : empty.cloud.labels) EXPECT_NE(label_class(l), LabelClass::kPerson);
}

}  // namespace
}  // namespace fieldlidar::sim
