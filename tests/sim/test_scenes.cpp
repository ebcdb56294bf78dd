// Every procedural scene builds deterministically, simulates, and carries its truth.

#include <cmath>
#include <map>
#include <set>

#include <gtest/gtest.h>

#include "fieldlidar/sim/lidar_simulator.hpp"
#include "fieldlidar/sim/motion.hpp"
#include "fieldlidar/sim/scenes.hpp"

namespace fieldlidar::sim {
namespace {

std::map<LabelClass, std::size_t> class_counts(const PointCloud& c) {
  std::map<LabelClass, std::size_t> n;
  for (auto l : c.labels) ++n[label_class(l)];
  return n;
}

class EveryScene : public ::testing::TestWithParam<SceneKind> {};

TEST_P(EveryScene, SimulatesAVlp16SweepAlongItsRoute) {
  const Scene scene = make_scene(GetParam(), 42);
  ASSERT_GE(scene.robot_route().size(), 2u);
  const auto motion = drive_scene_route(scene, 3.0);
  const LidarSimulator sim(scene, SensorModel::vlp16());
  const auto frame = sim.scan(1.0, motion.lidar_pose_fn());
  const auto& cloud = frame.cloud;
  EXPECT_TRUE(cloud.has_labels());
  EXPECT_TRUE(cloud.fields.ring && cloud.fields.time && cloud.fields.label);
  EXPECT_GT(cloud.size(), 8000u) << to_string(GetParam());  // of 28800 beams
  const auto n = class_counts(cloud);
  EXPECT_GT(n.at(LabelClass::kGround), cloud.size() / 20) << to_string(GetParam());
  EXPECT_EQ(n.count(LabelClass::kUnlabelled), 0u);
  for (const auto& p : cloud.points) {
    ASSERT_LT(p.ring, 16);
    ASSERT_GE(p.time, 0.f);
    ASSERT_LT(p.time, 0.1f);
  }
  // Points transformed with the true pose at their time land on the ground where labelled so.
  const auto T = motion.lidar_pose_fn();
  int checked = 0;
  for (std::size_t i = 0; i < cloud.size(); i += 37) {
    if (label_class(cloud.labels[i]) != LabelClass::kGround) continue;
    const auto& p = cloud.points[i];
    const Eigen::Vector3d w = T(1.0 + p.time) * Eigen::Vector3d(p.x, p.y, p.z);
    EXPECT_NEAR(w.z(), scene.ground_height_at(w.head<2>()), 0.15);
    ++checked;
  }
  EXPECT_GT(checked, 50);
}

INSTANTIATE_TEST_SUITE_P(Sim, EveryScene,
                         ::testing::Values(SceneKind::kLawn, SceneKind::kGreenhouse,
                                           SceneKind::kForest, SceneKind::kTerrain),
                         [](const auto& info) { return to_string(info.param); });

TEST(SimScenes, SameSeedSameSceneOtherSeedOtherScene) {
  for (auto kind :
       {SceneKind::kLawn, SceneKind::kGreenhouse, SceneKind::kForest, SceneKind::kTerrain}) {
    const Scene a = make_scene(kind, 5), b = make_scene(kind, 5), c = make_scene(kind, 6);
    ASSERT_EQ(a.mesh().size(), b.mesh().size());
    EXPECT_EQ(a.mesh().vertices.back(), b.mesh().vertices.back());
    EXPECT_NE(a.mesh().vertices.back(), c.mesh().vertices.back()) << to_string(kind);
  }
  EXPECT_EQ(scene_kind_from_string("forest"), SceneKind::kForest);
  EXPECT_FALSE(scene_kind_from_string("moon").has_value());
}

TEST(SimScenes, ForestTrunkPointsLieOnTheTrueTrunks) {
  ForestConfig cfg;
  cfg.trees_per_ha = 300;
  const Scene scene = make_forest_scene(cfg, 8);
  const double ha = cfg.size_x_m * cfg.size_y_m / 1e4;
  EXPECT_NEAR(double(scene.trunks().size()) / ha, 300.0, 60.0);
  int leaning = 0, forked = 0;
  for (const auto& t : scene.trunks()) {
    EXPECT_GE(t.dbh_m, 0.1);
    EXPECT_LE(t.dbh_m, 0.8);
    EXPECT_NEAR(t.axis.norm(), 1.0, 1e-9);
    EXPECT_NEAR(t.base_m.z(), scene.ground_height_at(t.base_m.head<2>()), 1e-6);
    leaning += t.leaning;
    forked += t.forked;
  }
  EXPECT_GT(leaning, 0);
  EXPECT_GT(forked, 0);
  const auto motion = drive_scene_route(scene, 2.0);
  SimConfig sc;
  sc.range_noise_m = 0.0;
  const auto frame =
      LidarSimulator(scene, SensorModel::vlp16(), sc).scan(0.5, motion.lidar_pose_fn());
  std::map<std::uint16_t, const TreeTruth*> by_id;
  for (const auto& t : scene.trunks()) by_id[t.id] = &t;
  std::set<std::uint16_t> seen;
  int checked = 0;
  for (std::size_t i = 0; i < frame.cloud.size(); ++i) {
    if (label_class(frame.cloud.labels[i]) != LabelClass::kTrunk) continue;
    const auto* t = by_id.at(label_instance(frame.cloud.labels[i]));
    seen.insert(t->id);
    const auto& p = frame.cloud.points[i];
    const Eigen::Vector3d w = motion.T_world_lidar(0.5 + p.time) * Eigen::Vector3d(p.x, p.y, p.z);
    const double along = (w - t->base_m).dot(t->axis);
    if (t->forked && along > t->fork_height_m - 0.2) continue;
    const double radial = ((w - t->base_m) - along * t->axis).norm();
    // Radius tapers linearly from DBH/2 at 1.3 m; facets sit up to 0.5 % inside the circle.
    const double expected = t->radius_at(along);
    EXPECT_NEAR(radial, expected, 0.006 * expected + 2e-3) << "tree " << t->id;
    ++checked;
  }
  EXPECT_GT(checked, 200);
  EXPECT_GT(seen.size(), 5u);
}

TEST(SimScenes, TiltingLaserInTheForest) {
  const Scene scene = make_forest_scene({}, 1);
  const auto motion = drive_scene_route(scene, 5.0);
  const auto sensor = SensorModel::tilting_2d();
  const auto frame = LidarSimulator(scene, sensor).scan(0.0, motion.lidar_pose_fn());
  EXPECT_EQ(frame.cloud.ring_count(), sensor.rings());
  auto n = class_counts(frame.cloud);
  EXPECT_GT(n[LabelClass::kTrunk], 500u);
  EXPECT_GT(n[LabelClass::kGround], 5000u);
}

TEST(SimScenes, TerrainTruthMarksSlopesPitsAndObstacles) {
  const Scene scene = make_terrain_scene({}, 3);
  const auto truth = scene.terrain_truth({.resolution_m = 0.5});
  EXPECT_NEAR(truth.geometry().resolution_m, 0.5, 1e-12);
  const auto slope = truth.layer("slope_deg");
  const auto passable = truth.layer("passable");
  float max_slope = 0;
  std::size_t blocked = 0;
  for (std::size_t i = 0; i < slope.size(); ++i) {
    max_slope = std::max(max_slope, slope[i]);
    blocked += passable[i] == 0.f;
  }
  EXPECT_GT(max_slope, 30.f);
  EXPECT_LT(max_slope, 89.f);  // the step's edge is the steepest place
  EXPECT_GT(blocked, slope.size() / 50);
  EXPECT_LT(blocked, slope.size() / 2);
  // Every rock's centre cell is blocked; the route is (almost) entirely passable.
  for (const auto& o : scene.obstacles())
    if (o.label == LabelClass::kObstacle && o.top_above_ground_m > 0.2) {
      EXPECT_EQ(*truth.value_at("passable", o.center_m), 0.f);
    }
  int on_route = 0, free_on_route = 0;
  for (const auto& p : scene.robot_route()) {
    ++on_route;
    free_on_route += *truth.value_at("passable", p) == 1.f;
  }
  EXPECT_GE(free_on_route, on_route - 1);
  // Overhanging branches are above the clearance: passable beneath them.
  for (const auto& o : scene.obstacles())
    if (o.bottom_above_ground_m > 1.5) {
      EXPECT_EQ(*truth.value_at("passable", o.center_m), 1.f);
    }
}

TEST(SimScenes, GreenhouseHasNarrowAislesBetweenRows) {
  const Scene scene = make_greenhouse_scene({}, 0);
  const auto motion = drive_scene_route(scene, 4.0);
  const auto frame = LidarSimulator(scene, SensorModel::vlp16()).scan(2.0, motion.lidar_pose_fn());
  auto n = class_counts(frame.cloud);
  EXPECT_GT(n[LabelClass::kStructure], 2000u);
  EXPECT_GT(n[LabelClass::kVegetation], 200u);
  // The robot stays in the first aisle (1 m wide, centred at y = 0.8 m).
  for (double t = 0; t <= 4.0; t += 0.5)
    EXPECT_NEAR(motion.T_world_base(t).translation().y(), 0.8, 0.2);
}

}  // namespace
}  // namespace fieldlidar::sim
