// Clustering: the grid and k-d tree searches against a brute-force oracle, PCL's size rules, the
// range-image region growing, and the label file values.

#include <random>

#include <gtest/gtest.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/segmentation/segment.hpp"
#include "seg_test_util.hpp"

namespace fieldlidar::segmentation {
namespace {

using test::canonical;

// Connected components of the "squared float distance < float(tol^2)" graph, O(n^2).
std::vector<std::vector<std::uint32_t>> oracle(const PointCloud& c, double tol, std::size_t min_pts,
                                               std::size_t max_pts) {
  const float r2 = float(tol * tol);
  std::vector<int> comp(c.size(), -1);
  std::vector<std::vector<std::uint32_t>> parts;
  for (std::size_t s = 0; s < c.size(); ++s) {
    if (comp[s] >= 0) continue;
    std::vector<std::uint32_t> q{std::uint32_t(s)};
    comp[s] = int(parts.size());
    for (std::size_t k = 0; k < q.size(); ++k)
      for (std::size_t j = 0; j < c.size(); ++j) {
        if (comp[j] >= 0) continue;
        const Point &a = c.points[q[k]], &b = c.points[j];
        const float dx = a.x - b.x, dy = a.y - b.y, dz = a.z - b.z;
        if (dx * dx + dy * dy + dz * dz < r2) {
          comp[j] = comp[s];
          q.push_back(std::uint32_t(j));
        }
      }
    parts.push_back(q);
  }
  std::vector<std::vector<std::uint32_t>> kept;
  for (auto& p : parts)
    if (p.size() >= min_pts && p.size() <= max_pts) kept.push_back(p);
  return canonical(kept);
}

std::vector<std::vector<std::uint32_t>> parts_of(const ClusterResult& r) {
  std::vector<std::vector<std::uint32_t>> p;
  for (const auto& c : r.clusters) p.push_back(c.indices);
  return canonical(p);
}

PointCloud random_blobs(std::uint32_t seed, int blobs, int per_blob, double spread) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> centre(-15, 15);
  std::normal_distribution<double> off(0, spread);
  PointCloud c;
  for (int b = 0; b < blobs; ++b) {
    const double cx = centre(rng), cy = centre(rng), cz = centre(rng) * 0.1;
    for (int k = 0; k < per_blob; ++k) {
      Point p;
      p.x = float(cx + off(rng));
      p.y = float(cy + off(rng));
      p.z = float(cz + off(rng));
      c.push_back(p);
    }
  }
  return c;
}

TEST(EuclideanClustering, GridAndKdTreeEqualTheBruteForceComponents) {
  for (std::uint32_t seed = 1; seed <= 6; ++seed)
    for (double tol : {0.2, 0.5, 1.3}) {
      const PointCloud c = random_blobs(seed, 25, 60, 0.15 + 0.05 * seed);
      const auto truth = oracle(c, tol, 5, 1000);
      ASSERT_GT(truth.size(), 0u);
      for (auto search :
           {EuclideanClusterConfig::Search::kGrid, EuclideanClusterConfig::Search::kKdTree}) {
        EuclideanClusterConfig cfg;
        cfg.tolerance_m = tol;
        cfg.min_points = 5;
        cfg.max_points = 1000;
        cfg.search = search;
        EXPECT_EQ(parts_of(cluster_euclidean(c, {}, cfg)), truth)
            << "seed " << seed << " tol " << tol << " search " << int(search);
      }
    }
}

// The grid search's other paths: columns whose points spread over a tall height range (sorted per
// column instead of by one counting sort), points beyond the dense column table (+-28 m at
// 0.5 m) and beyond the float cell indices (512 cells), and coordinates too large for int32 cell
// indices (the k-d tree takes over).
TEST(EuclideanClustering, GridFallbacksEqualTheBruteForceComponents) {
  const auto shifted = [](PointCloud c, float dx, float dy, float dz) {
    for (auto& p : c.points) {
      p.x += dx;
      p.y += dy;
      p.z += dz;
    }
    return c;
  };
  std::vector<std::pair<const char*, PointCloud>> cases;
  {
    PointCloud c = random_blobs(7, 10, 40, 0.2);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> z(0.f, 3000.f);
    for (int col = 0; col < 6; ++col)
      for (int k = 0; k < 40; ++k) {
        Point p;
        p.x = 20.f + 0.1f * float(col);
        p.y = -3.f;
        p.z = k % 4 == 0 ? 0.3f * float(k) : z(rng);  // a linked stack low, scattered above
        c.push_back(p);
      }
    cases.emplace_back("tall columns", c);
  }
  cases.emplace_back("beyond the dense table",
                     shifted(random_blobs(8, 15, 30, 0.2), 60.f, -45.f, 0));
  cases.emplace_back("beyond float cell indices",
                     shifted(random_blobs(9, 15, 30, 0.2), -400.f, 310.f, 2.f));
  {
    PointCloud c = random_blobs(10, 8, 30, 0.2);
    for (int k = 0; k < 3; ++k) {
      Point p;
      p.x = 6e8f + 100.f * float(k);
      p.y = 1.f;
      p.z = 0.5f;
      c.push_back(p);
    }
    cases.emplace_back("coordinates beyond int32 cells", c);
  }
  for (const auto& [name, cloud] : cases) {
    const auto truth = oracle(cloud, 0.5, 1, 100000);
    EuclideanClusterConfig cfg;
    cfg.min_points = 1;
    cfg.search = EuclideanClusterConfig::Search::kGrid;
    EXPECT_EQ(parts_of(cluster_euclidean(cloud, {}, cfg)), truth) << name;
  }
}

TEST(EuclideanClustering, ExactlyTheToleranceApartIsNotLinked) {
  // pcl's FLANN radius search keeps distances strictly below the radius; 0.5 and 0.25 are exact
  // in float.
  PointCloud c;
  for (int i = 0; i < 30; ++i) {
    Point p;
    p.x = 0.5f * float(i + 1);  // (0, 0, 0) would be a no-return
    c.push_back(p);
  }
  for (auto search :
       {EuclideanClusterConfig::Search::kGrid, EuclideanClusterConfig::Search::kKdTree}) {
    EuclideanClusterConfig cfg;
    cfg.min_points = 1;
    cfg.search = search;
    EXPECT_EQ(cluster_euclidean(c, {}, cfg).clusters.size(), 30u);
    cfg.tolerance_m = 0.5001;
    EXPECT_EQ(cluster_euclidean(c, {}, cfg).clusters.size(), 1u);
  }
}

TEST(EuclideanClustering, SizeLimitsSkipAndOrderFollowPcl) {
  // Three separated lines of 10, 21 and 40 points, plus skipped points bridging two of them.
  PointCloud c;
  std::vector<std::uint8_t> skip;
  auto line = [&](float y, int n) {
    for (int i = 0; i < n; ++i) {
      Point p;
      p.x = 0.1f * float(i);
      p.y = y;
      c.push_back(p);
      skip.push_back(0);
    }
  };
  line(0.f, 10);
  line(5.f, 21);
  line(10.f, 40);
  for (float y = 0.2f; y < 5.f; y += 0.2f) {  // would join line 0 and line 5 if not skipped
    Point p;
    p.y = y;
    c.push_back(p);
    skip.push_back(1);
  }
  EuclideanClusterConfig cfg;  // seed 002 defaults: 0.5 m, clusters of <= 20 points dropped
  ClusterResult r = cluster_euclidean(c, skip, cfg);
  ASSERT_EQ(r.clusters.size(), 2u);
  EXPECT_EQ(r.clusters[0].size(), 40u);  // largest first
  EXPECT_EQ(r.clusters[1].size(), 21u);
  EXPECT_EQ(r.cluster_of_point[0], -1);  // the 10-point line is noise
  EXPECT_EQ(r.cluster_of_point[10], 1);
  EXPECT_EQ(r.cluster_of_point[31], 0);
  EXPECT_EQ(r.cluster_of_point.back(), -1);  // skipped
  EXPECT_NEAR(r.clusters[0].centroid.x(), 0.1f * 39 / 2, 1e-4);
  EXPECT_FLOAT_EQ(r.clusters[0].max.x(), 0.1f * 39);
  EXPECT_FLOAT_EQ(r.clusters[0].min.y(), 10.f);
  cfg.max_points = 30;  // PCL drops clusters above the maximum, it does not split them
  r = cluster_euclidean(c, skip, cfg);
  ASSERT_EQ(r.clusters.size(), 1u);
  EXPECT_EQ(r.clusters[0].size(), 21u);
  cfg.tolerance_m = 0;
  EXPECT_THROW(cluster_euclidean(c, skip, cfg), Error);
}

TEST(RangeImageClustering, SeparatesObjectsDropsNoiseAndOutOfRange) {
  SensorModel vlp = SensorModel::vlp16();
  const std::vector<test::Box> boxes = {{{4, -1, -1.0}, {5, 1, 0.8}},       // near object
                                        {{4, 2.5, -1.0}, {4.6, 3.1, 0.8}},  // beside it, separate
                                        {{30, 8, -1.0}, {31, 10, 1.0}}};    // far object
  const PointCloud cloud = test::synthetic_scan(
      vlp, [](double, double) { return -1.0; }, boxes);
  std::vector<std::uint8_t> skip(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) skip[i] = cloud.labels[i] == 1;
  const RangeImage image = RangeImage::build(cloud, vlp);
  RangeImageClusterConfig cfg;
  ClusterResult r = cluster_range_image(cloud, image, skip, cfg);
  ASSERT_EQ(r.clusters.size(), 3u);
  for (const auto& cl : r.clusters) {  // each cluster is exactly one box
    const std::uint32_t label = cloud.labels[cl.indices.front()];
    for (std::uint32_t i : cl.indices) ASSERT_EQ(cloud.labels[i], label);
  }
  std::size_t box_points = 0;
  for (auto l : cloud.labels) box_points += l > 1;
  std::size_t clustered = 0;
  for (const auto& cl : r.clusters) clustered += cl.size();
  EXPECT_EQ(clustered, box_points);
  // seed 000: valid range S_s < S < S_m drops the far object.
  cfg.min_range_m = 1.0;
  cfg.max_range_m = 20.0;
  r = cluster_range_image(cloud, image, skip, cfg);
  EXPECT_EQ(r.clusters.size(), 2u);
  // Noise threshold above the far object's size drops it, keeps the near ones.
  cfg.max_range_m = 1e9;
  cfg.min_points = 40;
  r = cluster_range_image(cloud, image, skip, cfg);
  for (const auto& cl : r.clusters) EXPECT_GE(cl.size(), 40u);
}

TEST(Segment, LabelFileValues) {
  SensorModel vlp = SensorModel::vlp16();
  vlp.mounting_height_m = 1.0;
  PointCloud cloud = test::synthetic_scan(vlp, [](double, double) { return -1.0; },
                                          {{{4, -1, -1.0}, {5, 1, 0.8}}});
  Point nothing;  // a no-return
  cloud.push_back(nothing, 0);
  const SegmentResult r = segment(cloud, vlp);
  const auto labels = segment_labels(cloud, r);
  ASSERT_EQ(labels.size(), cloud.size());
  EXPECT_EQ(labels.back(), kLabelInvalid);
  std::size_t ground_ok = 0, ground_n = 0, in_cluster = 0;
  for (std::size_t i = 0; i + 1 < cloud.size(); ++i) {
    if (cloud.labels[i] == 1) {
      ++ground_n;
      ground_ok += labels[i] == kLabelGround;
    } else {
      in_cluster += labels[i] == kLabelClusterBase;
    }
  }
  EXPECT_GT(double(ground_ok), 0.98 * double(ground_n));
  EXPECT_GT(in_cluster, 100u);
}

}  // namespace
}  // namespace fieldlidar::segmentation
