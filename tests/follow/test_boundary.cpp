#include <gtest/gtest.h>

#include <cmath>

#include <nlohmann/json.hpp>

#include "fieldlidar/follow/boundary.hpp"

namespace fieldlidar::follow {
namespace {

std::vector<Eigen::Vector2d> dense_rectangle(double w, double h, double step) {
  std::vector<Eigen::Vector2d> pts;
  const std::vector<Eigen::Vector2d> c{{0, 0}, {w, 0}, {w, h}, {0, h}};
  for (int e = 0; e < 4; ++e) {
    const Eigen::Vector2d a = c[std::size_t(e)], b = c[std::size_t((e + 1) % 4)];
    const int n = int(std::round((b - a).norm() / step));
    for (int i = 0; i < n; ++i) pts.push_back(a + (b - a) * (double(i) / n));
  }
  return pts;
}

TEST(Boundary, RecordsOnlyWhileFollowingAndClosesToASimplePolygon) {
  BoundaryConfig cfg;
  cfg.record_spacing_m = 0.04;
  BoundaryRecorder rec(cfg);
  const auto pts = dense_rectangle(4, 3, 0.05);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    rec.record(pts[i], true);
    rec.record(Eigen::Vector2d(50, 50), false);  // stopped or lost: not recorded
  }
  EXPECT_EQ(rec.points().size(), pts.size());
  EXPECT_NEAR(rec.length_m(), 14.0 - 0.05, 1e-9);  // the closing edge is not walked
  const auto poly = rec.close();
  ASSERT_EQ(poly.vertices.size(), 4u);
  EXPECT_NEAR(poly.area_m2, 12.0, 1e-9);
  EXPECT_NEAR(poly.perimeter_m, 14.0, 1e-9);
  EXPECT_TRUE(poly.self_intersections.empty());
  EXPECT_GT(signed_area(poly.vertices), 0);  // counter-clockwise
}

TEST(Boundary, SimplifyKeepsCornersAndDropsNoiseBelowTolerance) {
  auto pts = dense_rectangle(10, 6, 0.1);
  for (std::size_t i = 0; i < pts.size(); ++i) pts[i] += Eigen::Vector2d(0, 0.01 * ((i % 3) - 1.0));
  const auto s = simplify_closed(pts, 0.03, 0.02);
  EXPECT_LE(s.size(), 8u);
  for (const auto& corner :
       {Eigen::Vector2d(10, 0), Eigen::Vector2d(10, 6), Eigen::Vector2d(0, 6)}) {
    double best = 1e9;
    for (const auto& v : s) best = std::min(best, (v - corner).norm());
    EXPECT_LT(best, 0.02);
  }
}

TEST(Boundary, SelfIntersectionOfABowtieIsFoundAtItsCrossing) {
  const std::vector<Eigen::Vector2d> bowtie{{0, 0}, {2, 2}, {2, 0}, {0, 2}};
  const auto x = find_self_intersections(bowtie);
  ASSERT_EQ(x.size(), 1u);
  EXPECT_EQ(x[0].edge_a, 0u);
  EXPECT_EQ(x[0].edge_b, 2u);
  EXPECT_NEAR((x[0].point_m - Eigen::Vector2d(1, 1)).norm(), 0, 1e-12);
  EXPECT_TRUE(find_self_intersections(dense_rectangle(3, 3, 0.5)).empty());
}

TEST(Boundary, CompareClosedGivesExactOffsetsOfNestedSquares) {
  const std::vector<Eigen::Vector2d> outer{{0, 0}, {10, 0}, {10, 10}, {0, 10}};
  const std::vector<Eigen::Vector2d> inner{{0.1, 0.1}, {9.9, 0.1}, {9.9, 9.9}, {0.1, 9.9}};
  const auto d = compare_closed(inner, outer, 0.05);
  EXPECT_NEAR(d.mean_m, 0.1, 1e-9);                      // every inner point is 0.1 from outer
  EXPECT_NEAR(d.hausdorff_m, 0.1 * std::sqrt(2), 1e-9);  // outer corners
  EXPECT_NEAR(compare_closed(outer, outer).hausdorff_m, 0, 1e-12);
}

TEST(Boundary, GeoJsonIsOneClosedPolygonInMetres) {
  BoundaryPolygon p;
  p.vertices = {{0, 0}, {4, 0}, {4, 3}, {0, 3}};
  p.area_m2 = 12;
  p.perimeter_m = 14;
  const auto j = nlohmann::json::parse(boundary_geojson(p, "world"));
  ASSERT_EQ(j["features"].size(), 1u);
  const auto& g = j["features"][0]["geometry"];
  EXPECT_EQ(g["type"], "Polygon");
  const auto& ring = g["coordinates"][0];
  ASSERT_EQ(ring.size(), 5u);
  EXPECT_EQ(ring[0], ring[4]);
  EXPECT_DOUBLE_EQ(ring[2][0].get<double>(), 4.0);
  EXPECT_DOUBLE_EQ(ring[2][1].get<double>(), 3.0);
  EXPECT_EQ(j["features"][0]["properties"]["frame"], "world");
  EXPECT_DOUBLE_EQ(j["features"][0]["properties"]["area_m2"].get<double>(), 12.0);
  const auto csv = boundary_csv(p);
  EXPECT_EQ(csv.substr(0, 10), "index,x,y\n");
  EXPECT_NE(csv.find("2,4.0000,3.0000\n"), std::string::npos);
}

}  // namespace
}  // namespace fieldlidar::follow
