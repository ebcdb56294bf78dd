// The local map's voxel store: its neighbour search against brute force, its capacity and crop.

#include <algorithm>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "fieldlidar/odometry/local_map.hpp"

namespace fieldlidar::odometry {
namespace {

// Points on a few planes and lines through a 12 m box, as a field scan leaves them.
std::vector<Eigen::Vector3f> surface_points(std::mt19937& rng, int count) {
  std::uniform_real_distribution<float> u(-6.f, 6.f), noise(-0.02f, 0.02f);
  std::vector<Eigen::Vector3f> out;
  for (int i = 0; i < count; ++i) {
    const float a = u(rng), b = u(rng);
    switch (i % 4) {
      case 0:
        out.emplace_back(a, b, -1.5f + noise(rng));
        break;  // ground
      case 1:
        out.emplace_back(a, 2.3f + noise(rng), 0.5f * b);
        break;  // a row of plants
      case 2:
        out.emplace_back(a, -2.7f + noise(rng), 0.5f * b);
        break;
      default:
        out.emplace_back(1.1f + noise(rng), 3.f + noise(rng), 0.4f * b);
        break;  // a post
    }
  }
  return out;
}

// The k nearest within the radius, by distance, from every point of the map.
std::vector<float> brute_force(const std::vector<Eigen::Vector3f>& pts, const Eigen::Vector3f& q,
                               int k, float radius) {
  std::vector<float> d2;
  for (const auto& p : pts)
    if (const float d = (p - q).squaredNorm(); d <= radius * radius) d2.push_back(d);
  std::sort(d2.begin(), d2.end());
  if (int(d2.size()) > k) d2.resize(std::size_t(k));
  return d2;
}

std::vector<float> sorted_distances(const std::vector<Eigen::Vector3f>& pts,
                                    const Eigen::Vector3f& q) {
  std::vector<float> d2;
  for (const auto& p : pts) d2.push_back((p - q).squaredNorm());
  std::sort(d2.begin(), d2.end());
  return d2;
}

TEST(VoxelMap, NearestMatchesBruteForce) {
  std::mt19937 rng(3);
  LocalMapConfig cfg;
  cfg.min_point_spacing_m = 0.05;
  VoxelMap map(cfg);
  map.insert(surface_points(rng, 20000));
  const auto pts = map.points();
  ASSERT_EQ(pts.size(), map.size());
  ASSERT_LT(map.size(), 20000u);  // full voxels dropped points
  std::uniform_real_distribution<float> u(-6.5f, 6.5f);
  std::vector<Eigen::Vector3f> found;
  int full = 0;
  for (int i = 0; i < 2000; ++i) {
    // Queries near the surfaces (most) and anywhere in the box.
    Eigen::Vector3f q(u(rng), u(rng), u(rng));
    if (i % 4 != 3) q = pts[std::size_t(i * 7919) % pts.size()] + 0.05f * q;
    map.nearest(q, found);
    const auto want = brute_force(pts, q, cfg.neighbours, float(cfg.max_neighbour_distance_m));
    // Every point within voxel_m / 2 of the query is seen, so the k nearest agree whenever the
    // k-th lies that near; farther ones come from the 8 nearest voxels only.
    if (!want.empty() && want.back() <= 0.25f) {
      ASSERT_EQ(sorted_distances(found, q), want) << "query " << i;
      full += int(found.size()) == cfg.neighbours;
    }
    for (const auto& p : found) EXPECT_LE((p - q).norm(), cfg.max_neighbour_distance_m);
  }
  EXPECT_GT(full, 1000);
}

TEST(VoxelMap, KeepsAtMostTheVoxelCapacity) {
  LocalMapConfig cfg;
  cfg.max_points_per_voxel = 7;
  cfg.min_point_spacing_m = 0.01;
  VoxelMap map(cfg);
  std::vector<Eigen::Vector3f> pts;
  for (int i = 0; i < 50; ++i) pts.emplace_back(0.1f + 0.015f * float(i), 0.5f, 0.5f);
  pts.emplace_back(0.1f, 0.5f, 0.505f);  // nearer than the spacing to the first: dropped
  map.insert(pts);
  EXPECT_EQ(map.voxel_count(), 1u);
  EXPECT_EQ(map.size(), 7u);
  const auto kept = map.points();
  for (int i = 0; i < 7; ++i) EXPECT_EQ(kept[std::size_t(i)], pts[std::size_t(i)]);
}

TEST(VoxelMap, CropKeepsNearVoxelsInOrder) {
  std::mt19937 rng(5);
  LocalMapConfig cfg;
  cfg.max_range_m = 4.0;
  VoxelMap map(cfg);
  map.insert(surface_points(rng, 5000));
  const auto before = map.points();
  map.crop(Eigen::Vector3d(2, 0, 0));
  const auto after = map.points();
  ASSERT_LT(after.size(), before.size());
  ASSERT_GT(after.size(), 0u);
  // The survivors keep their order (a subsequence of the points before).
  std::size_t j = 0;
  for (const auto& p : after) {
    while (j < before.size() && before[j] != p) ++j;
    ASSERT_LT(j, before.size());
    ++j;
  }
  // And the search still finds them (the table was rebuilt).
  std::vector<Eigen::Vector3f> found;
  for (std::size_t i = 0; i < after.size(); i += 37) {
    map.nearest(after[i], found);
    ASSERT_FALSE(found.empty());
    EXPECT_EQ(sorted_distances(found, after[i]).front(), 0.f);
  }
  // Points inserted after the crop land in new voxels as before.
  map.insert(std::vector<Eigen::Vector3f>{{30.f, 30.f, 30.f}});
  map.nearest({30.f, 30.f, 30.1f}, found);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0], Eigen::Vector3f(30.f, 30.f, 30.f));
}

}  // namespace
}  // namespace fieldlidar::odometry
