#include "cluster_common.hpp"

#include <algorithm>
#include <functional>

namespace fieldlidar::segmentation {
namespace {

/// The components of min_points..max_points points, largest first (`before` orders components
/// of equal size), and each component's rank among them (-1 if dropped).
struct KeptComponents {
  std::vector<std::uint32_t> kept;
  std::vector<std::int32_t> rank;
};

template <class Before>
KeptComponents keep_components(const std::vector<std::uint32_t>& count, std::size_t min_points,
                               std::size_t max_points, Before before) {
  KeptComponents out;
  for (std::size_t c = 0; c < count.size(); ++c)
    if (count[c] > 0 && count[c] >= min_points && count[c] <= max_points)
      out.kept.push_back(std::uint32_t(c));
  std::sort(out.kept.begin(), out.kept.end(), [&](std::uint32_t a, std::uint32_t b) {
    return count[a] != count[b] ? count[a] > count[b] : before(a, b);
  });
  out.rank.assign(count.size(), -1);
  for (std::size_t k = 0; k < out.kept.size(); ++k) out.rank[out.kept[k]] = std::int32_t(k);
  return out;
}

}  // namespace

void finish_cluster(const PointCloud& cloud, Cluster& cluster) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  cluster.min = Eigen::Vector3f::Constant(std::numeric_limits<float>::max());
  cluster.max = Eigen::Vector3f::Constant(std::numeric_limits<float>::lowest());
  for (std::uint32_t i : cluster.indices) {
    const Eigen::Vector3f p = cloud.points[i].xyz();
    sum += p.cast<double>();
    cluster.min = cluster.min.cwiseMin(p);
    cluster.max = cluster.max.cwiseMax(p);
  }
  if (cluster.indices.empty()) {
    cluster.min = cluster.max = cluster.centroid = Eigen::Vector3f::Zero();
    return;
  }
  cluster.centroid = (sum / double(cluster.indices.size())).cast<float>();
}

ClusterResult make_clusters(const PointCloud& cloud, const std::vector<std::int32_t>& component,
                            std::size_t component_count, std::size_t min_points,
                            std::size_t max_points) {
  std::vector<std::uint32_t> count(component_count, 0);
  std::vector<std::uint32_t> first(component_count, std::uint32_t(-1));
  for (std::size_t i = 0; i < component.size(); ++i) {
    const std::int32_t c = component[i];
    if (c < 0) continue;
    if (count[c]++ == 0) first[c] = std::uint32_t(i);
  }
  const auto [kept, rank] =
      keep_components(count, min_points, max_points,
                      [&](std::uint32_t a, std::uint32_t b) { return first[a] < first[b]; });
  ClusterResult out;
  out.clusters.resize(kept.size());
  for (std::size_t k = 0; k < kept.size(); ++k) out.clusters[k].indices.reserve(count[kept[k]]);
  out.cluster_of_point.assign(component.size(), -1);
  for (std::size_t i = 0; i < component.size(); ++i) {
    const std::int32_t c = component[i];
    if (c < 0 || rank[c] < 0) continue;
    out.cluster_of_point[i] = rank[c];
    out.clusters[rank[c]].indices.push_back(std::uint32_t(i));
  }
  for (auto& cl : out.clusters) finish_cluster(cloud, cl);
  return out;
}

ClusterResult make_clusters(std::size_t cloud_size, std::span<const std::uint32_t> active,
                            std::span<const ClusterPoint> xyz,
                            std::span<const std::int32_t> component, std::size_t component_count,
                            std::size_t min_points, std::size_t max_points) {
  // Component sizes, counted in runs (neighbouring points mostly share a component; an increment
  // in memory per point would chain each point to the previous one's store).
  std::vector<std::uint32_t> count(component_count, 0);
  {
    std::size_t run_c = 0, run = 0;
    for (const std::int32_t c : component) {
      if (std::size_t(c) != run_c) {
        count[run_c] += std::uint32_t(run);
        run_c = std::size_t(c);
        run = 0;
      }
      ++run;
    }
    if (run > 0) count[run_c] += std::uint32_t(run);
  }
  // Components are numbered by their first point: the lower number is the lower first index.
  const auto [kept, rank] = keep_components(count, min_points, max_points, std::less<>());
  ClusterResult out;
  out.clusters.resize(kept.size());
  for (std::size_t k = 0; k < kept.size(); ++k) out.clusters[k].indices.resize(count[kept[k]]);
  // Sums, bounds and indices in one pass in ascending point order: the same arithmetic, in the
  // same order, as finish_cluster. A run of points in one cluster keeps them in registers.
  struct Accumulator {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    Eigen::Vector3f min = Eigen::Vector3f::Constant(std::numeric_limits<float>::max());
    Eigen::Vector3f max = Eigen::Vector3f::Constant(std::numeric_limits<float>::lowest());
    std::size_t filled = 0;
  };
  std::vector<Accumulator> acc(kept.size());
  out.cluster_of_point.assign(cloud_size, -1);
  std::int32_t run_r = -1;
  Accumulator run;
  std::uint32_t* run_out = nullptr;
  for (std::size_t k = 0; k < component.size(); ++k) {
    const std::int32_t r = rank[std::size_t(component[k])];
    if (r < 0) continue;
    if (r != run_r) {
      if (run_r >= 0) acc[std::size_t(run_r)] = run;
      run_r = r;
      run = acc[std::size_t(r)];
      run_out = out.clusters[std::size_t(r)].indices.data();
    }
    const std::uint32_t i = active[k];
    out.cluster_of_point[i] = r;
    run_out[run.filled++] = i;
    const Eigen::Vector3f p(xyz[k].x, xyz[k].y, xyz[k].z);
    run.sum += p.cast<double>();
    run.min = run.min.cwiseMin(p);
    run.max = run.max.cwiseMax(p);
  }
  if (run_r >= 0) acc[std::size_t(run_r)] = run;
  for (std::size_t k = 0; k < kept.size(); ++k) {
    Cluster& cl = out.clusters[k];
    cl.min = acc[k].min;
    cl.max = acc[k].max;
    cl.centroid = (acc[k].sum / double(cl.indices.size())).cast<float>();
  }
  return out;
}

}  // namespace fieldlidar::segmentation
