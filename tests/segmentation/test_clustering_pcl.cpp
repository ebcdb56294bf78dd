// The k-d tree Euclidean clustering gives exactly pcl::EuclideanClusterExtraction's partition on
// the non-ground points of a real KITTI frame (PCL linked here as the oracle).

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/extract_clusters.h>

#include <gtest/gtest.h>

#include "fieldlidar/segmentation/segment.hpp"
#include "seg_test_util.hpp"
#include "test_data.hpp"

namespace fieldlidar::segmentation {
namespace {

struct PclPartition {
  std::vector<std::vector<std::uint32_t>> clusters;  ///< in PCL's order, input indices
};

PclPartition pcl_clusters(const PointCloud& cloud, const std::vector<std::uint8_t>& skip,
                          double tol, int min_size, int max_size) {
  pcl::PointCloud<pcl::PointXYZ>::Ptr sub(new pcl::PointCloud<pcl::PointXYZ>);
  std::vector<std::uint32_t> back;
  for (std::size_t i = 0; i < cloud.size(); ++i)
    if (!skip[i] && cloud.points[i].is_valid()) {
      sub->push_back({cloud.points[i].x, cloud.points[i].y, cloud.points[i].z});
      back.push_back(std::uint32_t(i));
    }
  pcl::search::KdTree<pcl::PointXYZ>::Ptr tree(new pcl::search::KdTree<pcl::PointXYZ>);
  tree->setInputCloud(sub);
  pcl::EuclideanClusterExtraction<pcl::PointXYZ> ec;
  ec.setClusterTolerance(tol);
  ec.setMinClusterSize(min_size);
  ec.setMaxClusterSize(max_size);
  ec.setSearchMethod(tree);
  ec.setInputCloud(sub);
  std::vector<pcl::PointIndices> found;
  ec.extract(found);
  PclPartition out;
  for (const auto& c : found) {
    std::vector<std::uint32_t> idx;
    for (int k : c.indices) idx.push_back(back[std::size_t(k)]);
    out.clusters.push_back(idx);
  }
  return out;
}

class KittiClusters : public ::testing::Test {
 protected:
  void SetUp() override {
    FIELDLIDAR_REQUIRE_DATA("kitti00/000000.bin");
    cloud = test::read_bin(fieldlidar::test::data_file("kitti00/000000.bin"));
    ground = ground_robust(cloud, SensorModel::hdl64e()).is_ground;
    std::size_t non_ground = 0;
    for (std::size_t i = 0; i < cloud.size(); ++i) non_ground += !ground[i];
    // The figure for this frame is ~52k non-ground points (Patchwork++'s split).
    ASSERT_GT(non_ground, 40000u);
    ASSERT_LT(non_ground, 70000u);
  }
  PointCloud cloud;
  std::vector<std::uint8_t> ground;
};

TEST_F(KittiClusters, SamePartitionAsPcl) {
  for (auto [tol, min_size] : {std::pair{0.5, 20}, std::pair{0.3, 5}, std::pair{1.0, 21}}) {
    const PclPartition pcl = pcl_clusters(cloud, ground, tol, min_size, 1000000);
    ASSERT_GT(pcl.clusters.size(), 20u);
    // PCL orders clusters by size, largest first (its order among equal sizes is unspecified).
    for (std::size_t k = 1; k < pcl.clusters.size(); ++k)
      ASSERT_GE(pcl.clusters[k - 1].size(), pcl.clusters[k].size());
    for (auto search :
         {EuclideanClusterConfig::Search::kGrid, EuclideanClusterConfig::Search::kKdTree}) {
      EuclideanClusterConfig cfg;
      cfg.tolerance_m = tol;
      cfg.min_points = std::size_t(min_size);
      cfg.search = search;
      const ClusterResult ours = cluster_euclidean(cloud, ground, cfg);
      std::vector<std::vector<std::uint32_t>> mine;
      for (const auto& c : ours.clusters) mine.push_back(c.indices);
      EXPECT_EQ(mine.size(), pcl.clusters.size()) << "tol " << tol << " search " << int(search);
      EXPECT_EQ(test::canonical(mine), test::canonical(pcl.clusters))
          << "tol " << tol << " search " << int(search);
      // Same sizes in the same order.
      for (std::size_t k = 0; k < std::min(mine.size(), pcl.clusters.size()); ++k)
        ASSERT_EQ(mine[k].size(), pcl.clusters[k].size()) << "cluster " << k;
      // Points outside every kept cluster are -1, the others point at their cluster.
      std::size_t in = 0;
      for (std::size_t i = 0; i < cloud.size(); ++i)
        if (ours.cluster_of_point[i] >= 0) {
          ++in;
          ASSERT_TRUE(std::binary_search(ours.clusters[ours.cluster_of_point[i]].indices.begin(),
                                         ours.clusters[ours.cluster_of_point[i]].indices.end(),
                                         std::uint32_t(i)));
        }
      std::size_t total = 0;
      for (const auto& c : mine) total += c.size();
      EXPECT_EQ(in, total);
    }
  }
}

}  // namespace
}  // namespace fieldlidar::segmentation
