// Trunks and DBH on real TLS plot files (forest_tls/), with the grid ground.
#include <cstdio>

#include <gtest/gtest.h>

#include "fieldlidar/forest/trunks.hpp"
#include "fieldlidar/io/cloud_file.hpp"
#include "fieldlidar/segmentation/ground.hpp"
#include "test_data.hpp"

namespace fieldlidar::forest {
namespace {

TreeResult plot_trees(const std::string& file) {
  const PointCloud cloud = io::read_cloud(test::data_file(file));
  const auto ground = segmentation::ground_grid(cloud);
  return extract_trees(cloud, ground.is_ground);
}

// Not tuned on: the defaults come from the simulated seed 1. 16 trees are found in this 10x10 m
// plot; 14 of them are long stems seen all round. The count has not been checked against a
// person's count of the stems yet, so the bounds only hold the figures measured.
TEST(ForestReal, PinePlot) {
  FIELDLIDAR_REQUIRE_DATA("forest_tls/pine_plot.las");
  const auto r = plot_trees("forest_tls/pine_plot.las");
  std::printf("pine_plot: %zu segments, %zu stacks, %zu trees\n", r.segments, r.stacks,
              r.trees.size());
  int plausible = 0;
  for (const auto& t : r.trees) {
    std::printf(
        "  tree %u at (%.2f, %.2f, %.2f) dbh %.3f arc %.0f res %.4f lines %zu seen "
        "%.1f-%.1f\n",
        t.id, t.base_m.x(), t.base_m.y(), t.base_m.z(), t.dbh_m, t.arc_deg, t.residual_m,
        t.observations, t.z_min_seen_m, t.z_max_seen_m);
    plausible += t.dbh_m > 0.10 && t.dbh_m < 0.40 && t.arc_deg > 270 && t.observations >= 30;
  }
  EXPECT_GE(r.trees.size(), 14u);
  EXPECT_LE(r.trees.size(), 18u);
  EXPECT_GE(plausible, 12);
}

// dbh.las is a 10 cm stem slice with no ground: the grid ground takes all of it, so no tree is
// made up; a circle fit over the slice gives a diameter. Its residual (~9 cm) says the slice is
// not one clean circle: the figure is printed, bounded loosely, and not yet checked.
TEST(ForestReal, DbhSlice) {
  FIELDLIDAR_REQUIRE_DATA("forest_tls/dbh.las");
  const PointCloud cloud = io::read_cloud(test::data_file("forest_tls/dbh.las"));
  const auto ground = segmentation::ground_grid(cloud);
  EXPECT_TRUE(extract_trees(cloud, ground.is_ground).trees.empty());
  std::vector<Eigen::Vector2d> xy;
  for (const auto& p : cloud.points) xy.emplace_back(p.x, p.y);
  const Circle c = fit_circle(xy, 0.03, 0.6, 30);
  std::printf("dbh.las: %zu points, diameter %.3f m, residual %.4f m, arc %.0f deg\n", cloud.size(),
              2 * c.radius_m, c.residual_m, arc_coverage_deg(xy, c.center));
  ASSERT_TRUE(c.ok);
  EXPECT_GT(2 * c.radius_m, 0.05);
  EXPECT_LT(2 * c.radius_m, 1.0);
}

}  // namespace
}  // namespace fieldlidar::forest
