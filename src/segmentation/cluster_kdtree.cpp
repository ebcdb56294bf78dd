// k-d tree search of the Euclidean clustering (nanoflann), breadth-first growth as in the seed
// and in PCL: the fallback of the voxel-cell search for coordinates beyond its range.

#include <cstddef>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include <nanoflann.hpp>

#include "cluster_euclidean_steps.hpp"

namespace fieldlidar::segmentation::detail {
namespace {

struct ActiveCloud {
  std::vector<ClusterPoint> pts;
  std::size_t kdtree_get_point_count() const { return pts.size(); }
  float kdtree_get_pt(std::size_t i, std::size_t dim) const {
    return dim == 0 ? pts[i].x : dim == 1 ? pts[i].y : pts[i].z;
  }
  template <class Bbox>
  bool kdtree_get_bbox(Bbox&) const {
    return false;
  }
};

using KdTree = nanoflann::KDTreeSingleIndexAdaptor<
    nanoflann::L2_Simple_Adaptor<float, ActiveCloud, float, std::uint32_t>, ActiveCloud, 3,
    std::uint32_t>;

}  // namespace

std::vector<std::int32_t> components_kdtree(std::span<const ClusterPoint> pts, float r2,
                                            std::size_t& count) {
  ActiveCloud data;
  data.pts.assign(pts.begin(), pts.end());
  const std::size_t n = data.pts.size();
  std::vector<std::int32_t> comp(n, -1);
  count = 0;
  if (n == 0) return comp;
  KdTree tree(3, data, nanoflann::KDTreeSingleIndexAdaptorParams(10));
  tree.buildIndex();
  const nanoflann::SearchParams params(32, 0.f, false);
  std::vector<std::pair<std::uint32_t, float>> matches;
  std::vector<std::uint32_t> queue;
  for (std::size_t seed = 0; seed < n; ++seed) {
    if (comp[seed] >= 0) continue;
    const auto id = std::int32_t(count++);
    comp[seed] = id;
    queue.assign(1, std::uint32_t(seed));
    for (std::size_t q = 0; q < queue.size(); ++q) {
      const ClusterPoint& p = data.pts[queue[q]];
      const float query[3] = {p.x, p.y, p.z};
      matches.clear();
      tree.radiusSearch(query, r2, matches, params);
      for (const auto& m : matches)
        if (comp[m.first] < 0) {
          comp[m.first] = id;
          queue.push_back(m.first);
        }
    }
  }
  return comp;
}

}  // namespace fieldlidar::segmentation::detail
