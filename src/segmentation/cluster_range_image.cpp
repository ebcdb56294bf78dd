// seed 000, step 2: cluster the non-ground returns by growing regions over range-image
// neighbours, drop small clusters as interference and clusters outside S_s < S < S_m.

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "cluster_common.hpp"
#include "fieldlidar/core/error.hpp"
#include "fieldlidar/segmentation/clustering.hpp"

namespace fieldlidar::segmentation {

ClusterResult cluster_range_image(const PointCloud& cloud, const RangeImage& image,
                                  std::span<const std::uint8_t> skip,
                                  const RangeImageClusterConfig& config) {
  if (image.point_cell.size() != cloud.size())
    throw Error("range-image clustering: the image was built for " +
                std::to_string(image.point_cell.size()) + " points, the cloud has " +
                std::to_string(cloud.size()));
  if (!skip.empty() && skip.size() != cloud.size())
    throw Error("range-image clustering: skip has " + std::to_string(skip.size()) +
                " entries for a cloud of " + std::to_string(cloud.size()) + " points");
  const int rows = image.rows, cols = image.cols;
  const std::size_t cells = std::size_t(rows) * cols;
  // A cell takes part when it holds a return that is not skipped.
  std::vector<std::int32_t> label(cells, -1);
  std::vector<std::uint8_t> active(cells, 0);
  for (std::size_t c = 0; c < cells; ++c) {
    const std::int32_t idx = image.cell_point[c];
    active[c] = idx >= 0 && (skip.empty() || !skip[idx]);
  }
  // depth_clustering's criterion: beta = atan2(d2 sin a, d1 - d2 cos a) > theta, d1 >= d2, where
  // a is the angle between the two beams. tan(beta) > tan(theta) avoids the atan2 per pair.
  const double tan_theta = std::tan(config.min_angle_deg * std::numbers::pi / 180.0);
  const float gap2 = float(config.max_gap_m * config.max_gap_m);
  auto make_step = [](double a) {
    return std::pair<float, float>(float(std::sin(a)), float(std::cos(a)));
  };
  std::vector<std::pair<float, float>> col_step(config.max_col_gap + 1);
  for (int k = 0; k <= config.max_col_gap; ++k)
    col_step[k] = make_step(k * 2.0 * std::numbers::pi / cols);
  auto row_step = [&](int r0, int r1) {
    if (image.row_altitude_rad.size() == std::size_t(rows))
      return make_step(std::abs(image.row_altitude_rad[r1] - image.row_altitude_rad[r0]));
    return make_step(std::abs(r1 - r0) * 0.4 * std::numbers::pi / 180.0);
  };
  std::vector<std::vector<std::pair<float, float>>> row_steps(rows);
  for (int r = 0; r < rows; ++r)
    for (int k = 1; k <= config.max_row_gap; ++k)
      row_steps[r].push_back(r + k < rows ? row_step(r, r + k) : std::pair<float, float>{0.f, 1.f});

  auto linked = [&](std::size_t a, std::size_t b, const std::pair<float, float>& step) {
    const float ra = image.cell_range_m[a], rb = image.cell_range_m[b];
    const float d1 = std::max(ra, rb), d2 = std::min(ra, rb);
    const float num = d2 * step.first, den = d1 - d2 * step.second;
    if (den <= 0.f || num > float(tan_theta) * den) return true;
    if (gap2 > 0.f) {
      const Point& p = cloud.points[image.cell_point[a]];
      const Point& q = cloud.points[image.cell_point[b]];
      const float dx = p.x - q.x, dy = p.y - q.y, dz = p.z - q.z;
      if (dx * dx + dy * dy + dz * dz < gap2) return true;
    }
    return false;
  };

  std::size_t count = 0;
  std::vector<std::uint32_t> queue;
  queue.reserve(4096);
  for (std::size_t seed = 0; seed < cells; ++seed) {
    if (!active[seed] || label[seed] >= 0) continue;
    const auto id = std::int32_t(count++);
    label[seed] = id;
    queue.assign(1, std::uint32_t(seed));
    for (std::size_t q = 0; q < queue.size(); ++q) {
      const std::uint32_t c = queue[q];
      const int r = int(c) / cols, col = int(c) % cols;
      auto visit = [&](int nr, int nc, const std::pair<float, float>& step) {
        const std::size_t n = std::size_t(nr) * cols + nc;
        if (!active[n] || label[n] >= 0) return;
        if (linked(c, n, step)) {
          label[n] = id;
          queue.push_back(std::uint32_t(n));
        }
      };
      for (int k = 1; k <= config.max_col_gap; ++k) {
        visit(r, (col + k) % cols, col_step[k]);
        visit(r, (col - k + cols) % cols, col_step[k]);
      }
      for (int k = 1; k <= config.max_row_gap; ++k) {
        if (r + k < rows) visit(r + k, col, row_steps[r][k - 1]);
        if (r - k >= 0) visit(r - k, col, row_steps[r - k][k - 1]);
      }
    }
  }
  // Every non-skipped point takes its cell's component (duplicates included).
  std::vector<std::int32_t> component(cloud.size(), -1);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const std::int32_t cell = image.point_cell[i];
    if (cell < 0 || (!skip.empty() && skip[i])) continue;
    component[i] = label[cell];
  }
  ClusterResult out = make_clusters(cloud, component, count, config.min_points, config.max_points);
  // seed 000: valid detection range S_s < S < S_m on the horizontal distance of the centroid.
  const bool range_filter = config.min_range_m > 0 || config.max_range_m < 1e9;
  if (range_filter) {
    std::vector<Cluster> kept;
    for (auto& cl : out.clusters) {
      const double s = std::hypot(double(cl.centroid.x()), double(cl.centroid.y()));
      if (s > config.min_range_m && s < config.max_range_m) kept.push_back(std::move(cl));
    }
    out.clusters = std::move(kept);
    std::fill(out.cluster_of_point.begin(), out.cluster_of_point.end(), -1);
    for (std::size_t k = 0; k < out.clusters.size(); ++k)
      for (std::uint32_t i : out.clusters[k].indices) out.cluster_of_point[i] = std::int32_t(k);
  }
  return out;
}

}  // namespace fieldlidar::segmentation
