// Step 2 of seed 003: segments stacked by vertical adjacency of their centroids.
#include <algorithm>
#include <cmath>

#include "fieldlidar/forest/trunks.hpp"

namespace fieldlidar::forest {

std::vector<std::vector<std::size_t>> stack_segments(std::span<const ScanSegment> segments,
                                                     const StackConfig& config) {
  std::vector<std::size_t> order(segments.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](auto a, auto b) { return segments[a].line < segments[b].line; });
  std::vector<std::vector<std::size_t>> stacks;
  for (auto s : order) {
    const auto& seg = segments[s];
    std::size_t best = stacks.size();
    double best_d = config.max_offset_m;
    for (std::size_t k = 0; k < stacks.size(); ++k) {
      const auto& top = segments[stacks[k].back()];
      const int gap = seg.line - top.line;
      if (gap < 1 || gap > config.max_line_gap + 1) continue;
      if (std::abs(seg.centroid.z() - top.centroid.z()) > config.max_step_m) continue;
      const double d = (seg.centroid.head<2>() - top.centroid.head<2>()).norm();
      if (d <= best_d) {
        best_d = d;
        best = k;
      }
    }
    if (best == stacks.size())
      stacks.push_back({s});
    else
      stacks[best].push_back(s);
  }
  std::vector<std::vector<std::size_t>> kept;
  for (auto& st : stacks) {
    if (st.size() < config.min_segments) continue;
    double lo = 1e30, hi = -1e30;
    for (auto s : st) {
      lo = std::min(lo, segments[s].centroid.z());
      hi = std::max(hi, segments[s].centroid.z());
    }
    if (hi - lo >= config.min_extent_m) kept.push_back(std::move(st));
  }
  return kept;
}

}  // namespace fieldlidar::forest
