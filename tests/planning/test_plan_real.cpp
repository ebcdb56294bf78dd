// Real data: Hybrid A* on the traversability map of the RELLIS-3D off-road OS1-64 sweep (one
// sweep, nothing tuned on it), from the sensor to goals on two rings round it (12 and 24 m, 16
// bearings each, the goal facing away from the sensor); every returned path's footprint checked
// against the scan's point labels: cells holding a tree, bush, fence or person return 0.15-1 m
// above the ground around it (what the robot would run into). The returns off the vehicle's own
// body (labelled void, within 2.3 m of the sensor) are dropped first, as `traversability
// --min-range` does. Unknown cells are planned over (the planner's default: a robot learns them as
// it comes close), so a path may cross a cell whose only return is an obstacle's.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "fieldlidar/io/cloud_file.hpp"
#include "fieldlidar/io/label_file.hpp"
#include "fieldlidar/planning/hybrid_astar.hpp"
#include "fieldlidar/terrain/traversability.hpp"
#include "test_data.hpp"

using namespace fieldlidar;
using namespace fieldlidar::planning;

namespace {

bool obstacle_class(std::uint32_t label) {
  const std::uint32_t c = label & 0xFFFF;
  return c == 4 || c == 17 || c == 18 || c == 19;  // tree, person, fence, bush
}

bool ground_class(std::uint32_t label) {
  const std::uint32_t c = label & 0xFFFF;
  return c == 1 || c == 3 || c == 10 || c == 23 || c == 31 || c == 33;  // dirt, grass, ...
}

/// Per cell of `g`: 1 when it holds an obstacle-class return 0.15-1 m above the ground there (the
/// lowest ground-class return in the cell and its 8 neighbours; `ground_m` where they hold none).
std::vector<std::uint8_t> labelled_obstacles(const GridGeometry& g, const PointCloud& cloud,
                                             const std::vector<std::uint32_t>& labels,
                                             double ground_m) {
  std::vector<double> lowest(g.cell_count(), std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < cloud.size(); ++i)
    if (ground_class(labels[i]))
      if (const auto cell = g.cell_of(cloud.points[i].xyz().cast<double>().head<2>())) {
        double& z = lowest[g.linear_index(cell->x(), cell->y())];
        z = std::min(z, double(cloud.points[i].z));
      }
  std::vector<std::uint8_t> out(g.cell_count(), 0);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (!obstacle_class(labels[i])) continue;
    const Eigen::Vector3d p = cloud.points[i].xyz().cast<double>();
    const auto cell = g.cell_of(p.head<2>());
    if (!cell) continue;
    double ground = std::numeric_limits<double>::infinity();
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx)
        if (g.contains(cell->x() + dx, cell->y() + dy))
          ground = std::min(ground, lowest[g.linear_index(cell->x() + dx, cell->y() + dy)]);
    if (!std::isfinite(ground)) ground = ground_m;
    if (p.z() > ground + 0.15 && p.z() < ground + 1.0)
      out[g.linear_index(cell->x(), cell->y())] = 1;
  }
  return out;
}

/// Median height of the grass, concrete and mud returns 3-6 m from the sensor (m, sensor frame).
double ground_z_m(const PointCloud& cloud, const std::vector<std::uint32_t>& labels) {
  std::vector<double> z;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const std::uint32_t c = labels[i] & 0xFFFF;
    const double r = cloud.points[i].xyz().head<2>().norm();
    if ((c == 3 || c == 23 || c == 33) && r > 3.0 && r < 6.0) z.push_back(cloud.points[i].z);
  }
  if (z.empty()) return 0.0;
  std::nth_element(z.begin(), z.begin() + z.size() / 2, z.end());
  return z[z.size() / 2];
}

}  // namespace

TEST(PlanReal, Rellis3dPathsKeepOffLabelledObstacles) {
  FIELDLIDAR_REQUIRE_DATA("rellis3d/000001.label");
  PointCloud cloud = io::read_cloud(fieldlidar::test::data_file("rellis3d/000001.bin"));
  cloud.labels = io::read_labels(fieldlidar::test::data_file("rellis3d/000001.label"));
  ASSERT_EQ(cloud.labels.size(), cloud.size());
  drop_nearer_than(cloud, 2.3);  // the labels follow their points
  const std::vector<std::uint32_t>& labels = cloud.labels;
  SensorModel sensor = SensorModel::os1_64();
  sensor.columns = 2048;
  const Grid2D map = terrain::map_scan(cloud, sensor, Pose::Identity());
  const GridGeometry& g = map.geometry();
  const double ground = ground_z_m(cloud, labels);
  const auto truth = labelled_obstacles(g, cloud, labels, ground);
  EXPECT_NEAR(ground, -1.26, 0.1);  // the sensor stands about 1.3 m above the ground

  HybridAStar planner(map, {});
  const terrain::RobotConfig robot;
  auto on_truth = [&](const Pose2& pose, bool* unknown) {
    bool hit = false;
    for (long c : rectangle_cells(g, pose, 0.5 * robot.length_m, 0.5 * robot.width_m))
      if (c >= 0 && truth[std::size_t(c)]) {
        hit = true;
        *unknown = *unknown || !planner.map().known(std::size_t(c));
      }
    return hit;
  };
  int planned = 0, refused = 0, refused_on_truth = 0, no_path = 0;
  int touching = 0, touching_known = 0;
  std::vector<double> ms;
  for (double radius : {12.0, 24.0})
    for (int k = 0; k < 16; ++k) {
      const double bearing = k * M_PI / 8.0;
      const Pose2 goal{radius * std::cos(bearing), radius * std::sin(bearing), bearing};
      const PlanResult r = planner.plan({0.0, 0.0, 0.0}, goal);
      bool goal_unknown = false;
      const bool goal_on_truth = on_truth(goal, &goal_unknown);
      if (r.status == PlanStatus::kGoalInCollision) {
        ++refused;
        refused_on_truth += goal_on_truth;
        continue;
      }
      if (!r.ok()) {
        ++no_path;
        std::printf("goal %4.0f m at %5.1f deg: %s\n", radius, bearing * 180 / M_PI,
                    to_string(r.status));
        continue;
      }
      ++planned;
      ms.push_back(r.search_ms + r.shortcut_ms + r.smooth_ms);
      bool touches = false, unknown = false;
      for (const PathPose& s : r.path) touches = on_truth(s.pose, &unknown) || touches;
      touching += touches;
      touching_known += touches && !unknown;
      if (touches)
        std::printf("goal %4.0f m at %5.1f deg: %.1f m, across a labelled obstacle (%s cell)\n",
                    radius, bearing * 180 / M_PI, path_length_m(r.path),
                    unknown ? "an unknown" : "a known");
    }
  std::sort(ms.begin(), ms.end());
  std::printf(
      "RELLIS-3D 000001: %d goals planned, %d refused in collision (%d of them on labelled "
      "obstacles), %d other failures; %d paths across labelled obstacle cells (%d of them "
      "cells the map knows); median plan %.1f ms\n",
      planned, refused, refused_on_truth, no_path, touching, touching_known,
      ms.empty() ? 0.0 : ms[ms.size() / 2]);
  // Measured: 23 planned, 9 refused (goals in the bushes and trees west and north; 6 on
  // labelled obstacle cells, 3 beside them), 0 other failures; 1 path across a labelled
  // obstacle cell: a fence return alone in a cell the map leaves unknown (24 m at 112.5 deg).
  // (Against a fixed ground height, 1.26 m under the sensor, a second path crossed 11 returns
  // labelled person 13.8 m away on the grass's own height where the ground rises: a label on the
  // ground, not an obstacle.)
  EXPECT_GE(planned, 20);
  EXPECT_EQ(no_path, 0);
  EXPECT_GE(refused_on_truth, refused - 3);
  EXPECT_EQ(touching_known, 0);  // never across a labelled obstacle the map has seen
  EXPECT_LE(touching, 1);
}
