// Trunks and DBH on real TLS plot files (forest_tls/), with the grid ground.
#include <cstdio>

#include <gtest/gtest.h>

#include "fieldlidar/forest/stem_slice.hpp"
#include "fieldlidar/forest/tracking.hpp"
#include "fieldlidar/forest/trunks.hpp"
#include "fieldlidar/io/cloud_file.hpp"
#include "fieldlidar/segmentation/ground.hpp"
#include "test_data.hpp"

namespace fieldlidar::forest {
namespace {

TreeResult plot_trees(const std::string& file) {
  const PointCloud cloud = io::read_cloud(test::data_file(file));
  const auto ground = segmentation::ground_grid(cloud);
  TreeConfig config;
  config.plot_full_view = true;
  return extract_trees(cloud, ground.is_ground, config);
}

// The defaults come from the simulated seed 1. In the PNG of the 1.2-1.4 m slice: 17 trees
// before (13 on a stem, 2 about 0.4 m off, 2 on nothing, 1 stem missed). Two stems were dropped on
// their fit residual (a branch whorl in the breast-height window pulled the start to r 0.26-0.28
// m); the per-bin start recovers one (0.177 m). Trees starting 2.0 and 1.5 m above the ground
// (one of them the 0.4 m off circle beside a missed stem) and a 15 m line of sparse slices are
// dropped as a plot seen all round: 16 trees.
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
  EXPECT_GE(r.trees.size(), 14u);  // measured 16
  EXPECT_LE(r.trees.size(), 17u);
  EXPECT_GE(plausible, 13);
}

// dbh.las is a 10 cm stem slice with no ground: the grid ground takes all of it, so no tree is
// made up; a circle fit over the slice gives a diameter. Its residual (~9 cm) says the slice is
// not one clean circle: the figure is printed, bounded loosely, and not yet checked.
// A 0.3 m slab of the pine plot (z 50.6-50.9 m, about 0.7-1.7 m above its sloping floor) as a
// forester's slice of a whole plot: one circle per stem, branches and needles left out, each
// on the stem the plot's trunk pipeline measures (within 0.1 m) with the same diameter within
// 3 cm where both see most of the stem (the slab cuts it 0.4 m lower or higher on the slope).
TEST(ForestReal, PinePlotSliceStems) {
  FIELDLIDAR_REQUIRE_DATA("forest_tls/pine_plot.las");
  const PointCloud plot = io::read_cloud(test::data_file("forest_tls/pine_plot.las"));
  PointCloud slab;
  slab.origin_m = plot.origin_m;
  for (const auto& p : plot.points)
    if (p.z + plot.origin_m.z() >= 50.6 && p.z + plot.origin_m.z() <= 50.9) slab.push_back(p);
  ASSERT_TRUE(is_stem_slice(slab));
  const auto stems = measure_slice_stems(slab);
  std::printf("pine_plot slab: %zu points, %zu stems\n", slab.size(), stems.size());
  EXPECT_GE(stems.size(), 15u);  // measured 17
  EXPECT_LE(stems.size(), 19u);
  const auto trees = plot_trees("forest_tls/pine_plot.las").trees;
  int compared = 0;
  for (const auto& t : trees) {
    if (t.arc_deg < 300 || t.observations < 40) continue;  // stems both see whole
    const Eigen::Vector2d at = t.at_height(1.3).head<2>();
    const StemSlice* near = nullptr;
    for (const auto& s : stems)
      if ((s.circle.center - at).norm() < 0.1) near = &s;
    ASSERT_NE(near, nullptr) << "no slice stem at " << at.transpose();
    if (near->arc_deg < 270) continue;  // (3.46, 1.51): 0.179 m over 198 deg, 0.137 m whole
    EXPECT_NEAR(2 * near->circle.radius_m, t.dbh_m, 0.03) << at.transpose();
    ++compared;
  }
  EXPECT_GE(compared, 8);
}

TEST(ForestReal, DbhSlice) {
  FIELDLIDAR_REQUIRE_DATA("forest_tls/dbh.las");
  const PointCloud cloud = io::read_cloud(test::data_file("forest_tls/dbh.las"));
  const auto ground = segmentation::ground_grid(cloud);
  EXPECT_TRUE(extract_trees(cloud, ground.is_ground).trees.empty());  // no stem 1 m tall
  ASSERT_TRUE(is_stem_slice(cloud));
  const StemSlice s = measure_stem_slice(cloud);
  std::vector<Eigen::Vector2d> xy;
  for (const auto& p : cloud.points) xy.emplace_back(p.x, p.y);
  const Circle all = fit_circle(xy, 0.03, 1.5, 30);
  std::printf(
      "dbh.las: %zu points, z %.3f-%.3f m; stem circle at (%.3f, %.3f) diameter %.3f m, "
      "residual %.4f m, %zu "
      "inliers, arc %.0f deg; a least-squares circle through every point: %.3f m, residual "
      "%.4f m\n",
      s.points, s.z_min_m, s.z_max_m, s.circle.center.x() + cloud.origin_m.x(),
      s.circle.center.y() + cloud.origin_m.y(), 2 * s.circle.radius_m, s.circle.residual_m,
      s.inliers, s.arc_deg, 2 * all.radius_m, all.residual_m);
  ASSERT_TRUE(s.circle.ok);
  EXPECT_NEAR(2 * s.circle.radius_m, 0.28, 0.03);
}

}  // namespace
}  // namespace fieldlidar::forest

namespace fieldlidar::forest {
namespace {

// SLOAM's trunks of a scan: its trunk points clustered in 2D (0.5 m links), one centroid each.
std::vector<Eigen::Vector2d> sloam_trunks(const PointCloud& trunk_points) {
  std::vector<Eigen::Vector2d> pts, out;
  for (const auto& p : trunk_points.points)
    if (p.is_valid()) pts.emplace_back(p.x, p.y);
  std::vector<int> label(pts.size(), -1);
  int n = 0;
  for (std::size_t s = 0; s < pts.size(); ++s) {
    if (label[s] >= 0) continue;
    std::vector<std::size_t> todo{s};
    label[s] = n;
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    std::size_t count = 0;
    while (!todo.empty()) {
      const auto k = todo.back();
      todo.pop_back();
      sum += pts[k];
      ++count;
      for (std::size_t j = 0; j < pts.size(); ++j)
        if (label[j] < 0 && (pts[j] - pts[k]).norm() < 0.5) label[j] = n, todo.push_back(j);
    }
    if (count >= 20) out.push_back(sum / double(count));
    ++n;
  }
  return out;
}

struct SloamScan {
  PointCloud cloud;
  std::vector<std::uint8_t> ground;
  std::vector<Eigen::Vector2d> sloam;
};

SloamScan sloam_scan(const std::string& name) {
  SloamScan s;
  const PointCloud trunks = io::read_cloud(test::data_file("forest_sloam/" + name));
  std::string other = name;
  other.replace(other.find("tree"), 4, "ground");
  s.cloud = io::read_cloud(test::data_file("forest_sloam/" + other));
  for (const auto& p : trunks.points) s.cloud.push_back(p);
  s.ground = segmentation::ground_grid(s.cloud).is_ground;
  s.sloam = sloam_trunks(trunks);
  return s;
}

TEST(ForestReal, SloamScans) {
  FIELDLIDAR_REQUIRE_DATA("forest_sloam/still_tree_t0.pcd");
  for (const char* name :
       {"still_tree_t0.pcd", "still_tree_t1.pcd", "moving_tree_t0.pcd", "moving_tree_t1.pcd"}) {
    const auto s = sloam_scan(name);
    const auto r = extract_trees(s.cloud, s.ground);
    int found = 0;
    for (const auto& c : s.sloam) {
      bool hit = false;
      for (const auto& t : r.trees)
        hit |= (t.at_height(1.3).head<2>() - c).norm() < 0.3 + t.dbh_m / 2;
      found += hit;
    }
    int extra = 0;
    for (const auto& t : r.trees) {
      bool near = false;
      for (const auto& c : s.sloam)
        near |= (t.at_height(1.3).head<2>() - c).norm() < 0.3 + t.dbh_m / 2;
      if (!near) {
        ++extra;
        std::printf("    extra: (%.2f, %.2f) range %.1f dbh %.3f arc %.0f res %.4f lines %zu\n",
                    t.base_m.x(), t.base_m.y(), t.base_m.head<2>().norm(), t.dbh_m, t.arc_deg,
                    t.residual_m, t.observations);
      }
    }
    std::printf(
        "%s: %zu points (rings: %d), SLOAM trunks %zu, ours %zu, SLOAM's found %d, extra %d\n",
        name, s.cloud.size(), int(s.cloud.fields.ring), s.sloam.size(), r.trees.size(), found,
        extra);
    EXPECT_GE(found, 15);  // measured 19-29 of SLOAM's 32-44 clusters
  }
}

// Relative pose t0 -> t1 from the trunks (no prior beyond a 1.5 m gate) and the ground planes.
TEST(ForestReal, SloamRelativePose) {
  FIELDLIDAR_REQUIRE_DATA("forest_sloam/still_tree_t0.pcd");
  for (const char* pair : {"still", "moving"}) {
    const auto a = sloam_scan(std::string(pair) + "_tree_t0.pcd");
    const auto b = sloam_scan(std::string(pair) + "_tree_t1.pcd");
    const auto ta = extract_trees(a.cloud, a.ground).trees,
               tb = extract_trees(b.cloud, b.ground).trees;
    const auto la = landmarks_of(ta), lb = landmarks_of(tb);
    AssociationConfig ac;
    ac.gate_m = 1.5;
    const auto m = associate_trunks(la, lb, Pose::Identity(), ac);
    const Pose T =
        estimate_trunk_motion(la, lb, m, fit_ground_plane(a.cloud, a.ground, 2, 15),
                              fit_ground_plane(b.cloud, b.ground, 2, 15), Pose::Identity());
    const Eigen::AngleAxisd aa(T.linear());
    std::printf(
        "%s t0->t1: %zu matches, translation (%.3f, %.3f, %.3f) = %.3f m, rotation %.2f deg\n",
        pair, m.size(), T.translation().x(), T.translation().y(), T.translation().z(),
        T.translation().norm(), aa.angle() * 180 / M_PI);
    EXPECT_GE(m.size(), 5u);
  }
}

}  // namespace
}  // namespace fieldlidar::forest
