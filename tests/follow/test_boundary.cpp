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

namespace fieldlidar::follow {
namespace {

TEST(Boundary, OpenOrSelfCrossingBoundaryIsALineStringNeverAPolygon) {
  BoundaryPolygon open;
  open.vertices = {{0, 0}, {4, 0}, {4, 3}};
  open.closed = false;  // a time limit, no stop command
  EXPECT_EQ(boundary_shape(open), BoundaryShape::kOpenPath);
  auto j = nlohmann::json::parse(boundary_geojson(open, "world"));
  auto g = j["features"][0]["geometry"];
  EXPECT_EQ(g["type"], "LineString");
  ASSERT_EQ(g["coordinates"].size(), 3u);  // not joined back to the start
  EXPECT_FALSE(j["features"][0]["properties"]["closed"].get<bool>());
  EXPECT_DOUBLE_EQ(j["features"][0]["properties"]["length_m"].get<double>(), 7.0);

  BoundaryPolygon bowtie;
  bowtie.vertices = {{0, 0}, {4, 3}, {4, 0}, {0, 3}};
  bowtie.self_intersections = find_self_intersections(bowtie.vertices);
  ASSERT_FALSE(bowtie.self_intersections.empty());
  EXPECT_EQ(boundary_shape(bowtie), BoundaryShape::kSelfIntersecting);
  j = nlohmann::json::parse(boundary_geojson(bowtie, "world"));
  g = j["features"][0]["geometry"];
  EXPECT_EQ(g["type"], "LineString");
  ASSERT_EQ(g["coordinates"].size(), 5u);
  EXPECT_EQ(g["coordinates"][0], g["coordinates"][4]);
}

TEST(Boundary, GeoJsonWithAnOriginIsWgs84LonLat) {
  BoundaryPolygon p;
  p.vertices = {{0, 0}, {100, 0}, {100, 50}, {0, 50}};
  p.area_m2 = 5000;
  p.perimeter_m = 300;
  const GeoOrigin origin{.lat_deg = 48.0, .lon_deg = 11.0, .heading_deg = 90};
  const auto j = nlohmann::json::parse(boundary_geojson(p, "world", origin));
  const auto& ring = j["features"][0]["geometry"]["coordinates"][0];
  ASSERT_EQ(ring.size(), 5u);
  EXPECT_DOUBLE_EQ(ring[0][0].get<double>(), 11.0);
  EXPECT_DOUBLE_EQ(ring[0][1].get<double>(), 48.0);
  // WGS84 at 48 deg: 1 deg of longitude 74,625.35 m, of latitude 111,190.32 m (radii of curvature).
  EXPECT_NEAR(ring[1][0].get<double>() - 11.0, 100.0 / 74625.35, 1e-8);
  EXPECT_NEAR(ring[1][1].get<double>(), 48.0, 1e-12);
  EXPECT_NEAR(ring[2][1].get<double>() - 48.0, 50.0 / 111190.32, 1e-8);
  EXPECT_EQ(j["features"][0]["properties"]["local_coordinates_m"][1][0].get<double>(), 100.0);
  // Heading 0: the local +x axis points north.
  const auto n = local_to_lon_lat({100, 0}, {.lat_deg = 48.0, .lon_deg = 11.0, .heading_deg = 0});
  EXPECT_NEAR(n.x(), 11.0, 1e-12);
  EXPECT_NEAR(n.y() - 48.0, 100.0 / 111190.32, 1e-8);
  EXPECT_THROW(parse_geo_origin("48.0", "--origin"), std::exception);
  EXPECT_THROW(parse_geo_origin("95,11", "--origin"), std::exception);
  EXPECT_EQ(parse_geo_origin("48.5,-3.25,30", "--origin").heading_deg, 30.0);
}

}  // namespace
}  // namespace fieldlidar::follow
