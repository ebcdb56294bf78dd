// The follow pipeline's 3D person detector on sweeps of a LiDAR truly mounted tilted (the
// simulator casts the tilted beams): given the tilted pose, the sweep is levelled and the body
// check follows the tilted beams, and the operator is found where the level mount finds them.

#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "fieldlidar/follow/pipeline.hpp"
#include "fieldlidar/sim/lidar_simulator.hpp"
#include "fieldlidar/sim/motion.hpp"
#include "fieldlidar/sim/scenes.hpp"

namespace fieldlidar {
namespace {

struct Found {
  double operator_miss_m = INFINITY;  ///< to the nearest person reported (inf: none)
  int others = 0;                     ///< persons reported farther than 0.5 m from the operator
};

/// The persons the detector reports in one sweep at t0_s of `sensor` mounted on the following
/// mower rotated by `mount`, against the operator (the scene's only person).
Found operator_found(const sim::Scene& scene, const SensorModel& sensor,
                     const Eigen::Matrix3d& mount, double t0_s) {
  const auto motion = sim::follow_operator(scene, 1, t0_s + 1.0);
  const auto pose = [&motion, &mount](double t) {
    Pose T = motion.T_world_lidar(t);
    T.linear() = T.linear() * mount;
    return T;
  };
  const sim::LidarSimulator lidar(scene, sensor);
  const PointCloud cloud = lidar.scan(t0_s, pose).cloud;
  const follow::Perception per =
      follow::perceive(cloud, sensor, pose(t0_s), follow::FollowConfig{});
  const Eigen::Vector2d truth = scene.people_at(t0_s)[0].position_m;
  Found f;
  for (const auto& p : per.people_m) {
    f.operator_miss_m = std::min(f.operator_miss_m, (p - truth).norm());
    f.others += (p - truth).norm() > 0.5;
  }
  return f;
}

Eigen::Matrix3d rot(double deg, const Eigen::Vector3d& axis) {
  return Eigen::AngleAxisd(deg * std::numbers::pi / 180.0, axis).toRotationMatrix();
}

// Lawn scene 2, the operator 2-3 m ahead at 10 s and 14 s. Measured: found within 0.2 m by the
// level mount and by every tilted one; at 14 s one more person 0.5 m or more off by three of
// the six mounts, the level ones among them (a single sweep: the tracker has not judged it) (the
// VLP-16 pitched 10 deg either way or rolled 10 deg, an HDL-32E, whose beams reach 30.7 deg down
// and 10.7 deg up, turned over).
TEST(TiltedMountPeople, OperatorFoundAsByTheLevelMount) {
  const sim::Scene scene = sim::make_lawn_scene({}, 2);
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX(), y = Eigen::Vector3d::UnitY();
  struct Case {
    const char* name;
    SensorModel sensor;
    Eigen::Matrix3d mount;
  };
  const Case cases[] = {{"level", SensorModel::vlp16(), Eigen::Matrix3d::Identity()},
                        {"nose down 10", SensorModel::vlp16(), rot(10, y)},
                        {"nose up 10", SensorModel::vlp16(), rot(-10, y)},
                        {"rolled 10", SensorModel::vlp16(), rot(10, x)},
                        {"hdl32e level", SensorModel::hdl32e(), Eigen::Matrix3d::Identity()},
                        {"hdl32e upside down", SensorModel::hdl32e(), rot(180, x)}};
  for (const double t0 : {10.0, 14.0})
    for (const Case& c : cases) {
      const Found f = operator_found(scene, c.sensor, c.mount, t0);
      std::printf("%s at %.0f s: operator %.2f m from the nearest person, %d other persons\n",
                  c.name, t0, f.operator_miss_m, f.others);
      EXPECT_LT(f.operator_miss_m, 0.3) << c.name << " at " << t0 << " s";
      EXPECT_LE(f.others, 1) << c.name << " at " << t0 << " s";
    }
}

}  // namespace
}  // namespace fieldlidar
