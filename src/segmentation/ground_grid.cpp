// Ground of a cloud that is not one sensor sweep (an airborne or terrestrial survey, a merged
// map): a simple morphological filter (Pingel, Clarke & McBride 2013, "SMRF") on a grid of
// lowest returns. No rings, no sensor origin: only z up.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/segmentation/ground.hpp"
#include "polar_grid.hpp"

namespace fieldlidar::segmentation {
namespace {

constexpr float kEmpty = std::numeric_limits<float>::infinity();

struct Grid {
  int nx = 0, ny = 0;
  double x0 = 0, y0 = 0, cell = 1;
  std::vector<float> z;  ///< row-major (y rows), kEmpty where no value
  float& at(int ix, int iy) { return z[std::size_t(iy) * nx + ix]; }
  float at(int ix, int iy) const { return z[std::size_t(iy) * nx + ix]; }
};

// Min (or max) over a centred window of 2r + 1 samples along a line of n samples `stride` apart,
// in O(n) whatever r (van Herk / Gil-Werman). Samples beyond the ends do not take part.
void line_extreme(float* v, int n, std::size_t stride, int r, bool take_min, std::vector<float>& g,
                  std::vector<float>& h) {
  const int w = 2 * r + 1, m = n + 2 * r;
  const float neutral = take_min ? kEmpty : -kEmpty;
  const auto op = [take_min](float a, float b) {
    return take_min ? std::min(a, b) : std::max(a, b);
  };
  const auto padded = [&](int i) {
    return i < r || i >= n + r ? neutral : v[std::size_t(i - r) * stride];
  };
  g.resize(std::size_t(m));
  h.resize(std::size_t(m));
  for (int i = 0; i < m; ++i) g[i] = i % w == 0 ? padded(i) : op(g[i - 1], padded(i));
  for (int i = m - 1; i >= 0; --i)
    h[i] = (i % w == w - 1 || i == m - 1) ? padded(i) : op(h[i + 1], padded(i));
  for (int j = 0; j < n; ++j) v[std::size_t(j) * stride] = op(h[j], g[j + 2 * r]);
}

// Square-window erosion (take_min) or dilation of the whole grid, radius r cells.
void filter(Grid& grid, int r, bool take_min) {
  std::vector<float> g, h;
  for (int iy = 0; iy < grid.ny; ++iy) line_extreme(&grid.at(0, iy), grid.nx, 1, r, take_min, g, h);
  for (int ix = 0; ix < grid.nx; ++ix)
    line_extreme(&grid.at(ix, 0), grid.ny, std::size_t(grid.nx), r, take_min, g, h);
}

// Empty cells take the mean of their filled 8-neighbours, ring after ring inward.
void fill_empty(Grid& grid) {
  std::vector<std::size_t> empty;
  for (std::size_t k = 0; k < grid.z.size(); ++k)
    if (grid.z[k] == kEmpty) empty.push_back(k);
  std::vector<std::pair<std::size_t, float>> filled;
  while (!empty.empty()) {
    filled.clear();
    std::size_t kept = 0;
    for (const std::size_t k : empty) {
      const int ix = int(k % std::size_t(grid.nx)), iy = int(k / std::size_t(grid.nx));
      double sum = 0;
      int n = 0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int jx = ix + dx, jy = iy + dy;
          if (jx < 0 || jy < 0 || jx >= grid.nx || jy >= grid.ny) continue;
          const float z = grid.at(jx, jy);
          if (z != kEmpty) {
            sum += z;
            ++n;
          }
        }
      if (n > 0)
        filled.emplace_back(k, float(sum / n));
      else
        empty[kept++] = k;
    }
    if (filled.empty()) return;  // nothing to fill from
    for (const auto& [k, z] : filled) grid.z[k] = z;
    empty.resize(kept);
  }
}

// Cells far below the median of their filled neighbours: multipath and bird-strike noise, which
// would otherwise drag the whole surface around them down. Emptied.
void drop_low_outliers(Grid& grid, double low_outlier_m) {
  std::vector<std::size_t> low;
  std::vector<float> around;
  for (int iy = 0; iy < grid.ny; ++iy)
    for (int ix = 0; ix < grid.nx; ++ix) {
      const float z = grid.at(ix, iy);
      if (z == kEmpty) continue;
      around.clear();
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int jx = ix + dx, jy = iy + dy;
          if ((dx == 0 && dy == 0) || jx < 0 || jy < 0 || jx >= grid.nx || jy >= grid.ny) continue;
          if (grid.at(jx, jy) != kEmpty) around.push_back(grid.at(jx, jy));
        }
      if (around.size() < 3) continue;
      const auto mid = around.begin() + std::ptrdiff_t(around.size() / 2);
      std::nth_element(around.begin(), mid, around.end());
      if (double(*mid) - z > low_outlier_m) low.push_back(std::size_t(iy) * grid.nx + ix);
    }
  for (const std::size_t k : low) grid.z[k] = kEmpty;
}

}  // namespace

GroundResult ground_grid(const PointCloud& cloud, const GridGroundConfig& config_in) {
  if (!(config_in.cell_m >= 0) || !std::isfinite(config_in.cell_m))
    throw Error("grid ground: GridGroundConfig.cell_m must be >= 0 (got " +
                std::to_string(config_in.cell_m) + ")");
  GroundResult result;
  result.is_ground.assign(cloud.size(), 0);
  Bounds3 b;
  std::size_t valid = 0;
  for (const Point& p : cloud.points)
    if (valid_point(p)) {
      b.extend(p.xyz().cast<double>());
      ++valid;
    }
  if (b.empty()) return result;
  if (const auto why = implausible_span(b)) throw Error("grid ground: " + *why);
  GridGroundConfig config = config_in;
  if (config.cell_m == 0) {
    const double area = std::max(1.0, (b.max.x() - b.min.x()) * (b.max.y() - b.min.y()));
    config.cell_m =
        std::clamp(3.0 / std::sqrt(double(valid) / area), config.min_cell_m, config.max_cell_m);
  }

  Grid lowest;
  lowest.cell = config.cell_m;
  lowest.x0 = b.min.x();
  lowest.y0 = b.min.y();
  const double nx = std::floor((b.max.x() - b.min.x()) / config.cell_m) + 1;
  const double ny = std::floor((b.max.y() - b.min.y()) / config.cell_m) + 1;
  if (nx * ny > double(config.max_cells)) {
    // A survey of many square kilometres: its cells would not fit, and are no larger than
    // max_cell_m when chosen from the density.
    char text[200];
    std::snprintf(text, sizeof text,
                  "grid ground: the cloud spans %.0f x %.0f m, more than %zu cells of %g m: "
                  "split it into tiles",
                  b.max.x() - b.min.x(), b.max.y() - b.min.y(), config.max_cells, config.cell_m);
    throw Error(text);
  }
  lowest.nx = int(nx);
  lowest.ny = int(ny);
  lowest.z.assign(std::size_t(lowest.nx) * lowest.ny, kEmpty);
  const auto cell_of = [&lowest](const Point& p) {
    const int ix = std::clamp(int((p.x - lowest.x0) / lowest.cell), 0, lowest.nx - 1);
    const int iy = std::clamp(int((p.y - lowest.y0) / lowest.cell), 0, lowest.ny - 1);
    return std::pair{ix, iy};
  };
  for (const Point& p : cloud.points) {
    if (!valid_point(p)) continue;
    const auto [ix, iy] = cell_of(p);
    lowest.at(ix, iy) = std::min(lowest.at(ix, iy), p.z);
  }
  drop_low_outliers(lowest, config.low_outlier_m);
  const std::vector<float> observed = lowest.z;  // lowest returns, outliers emptied
  fill_empty(lowest);

  // Progressive opening: a cell the opening of radius r lowers by more than max_slope times the
  // radius step, compared with the previous radius, is an object's.
  std::vector<std::uint8_t> object(lowest.z.size(), 0);
  Grid last = lowest;
  const int max_radius = std::max(1, int(std::ceil(0.5 * config.max_window_m / config.cell_m)));
  for (int r = 1; r <= max_radius; ++r) {
    Grid opened = last;
    filter(opened, r, true);
    filter(opened, r, false);
    const float threshold = float(config.max_slope * config.cell_m);  // one cell more of radius
    for (std::size_t k = 0; k < object.size(); ++k)
      if (last.z[k] - opened.z[k] > threshold * float(r)) object[k] = 1;
    last = std::move(opened);
  }

  // The ground surface: lowest returns of the cells not on objects, the rest filled in.
  Grid surface = lowest;
  surface.z = observed;
  for (std::size_t k = 0; k < object.size(); ++k)
    if (object[k]) surface.z[k] = kEmpty;
  fill_empty(surface);

  // Each point against the surface, bilinear between cell centres, with the tolerance growing
  // with the local slope (a cell's lowest return lies on its downhill edge).
  const auto value = [&surface](int ix, int iy) {
    return surface.at(std::clamp(ix, 0, surface.nx - 1), std::clamp(iy, 0, surface.ny - 1));
  };
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Point& p = cloud.points[i];
    if (!valid_point(p)) continue;
    const double u = (p.x - surface.x0) / surface.cell - 0.5,
                 v = (p.y - surface.y0) / surface.cell - 0.5;
    const int ix = int(std::floor(u)), iy = int(std::floor(v));
    const double fu = u - ix, fv = v - iy;
    const double z00 = value(ix, iy), z10 = value(ix + 1, iy), z01 = value(ix, iy + 1),
                 z11 = value(ix + 1, iy + 1);
    if (!std::isfinite(z00 + z10 + z01 + z11)) continue;  // no ground anywhere
    const double ground = (1 - fv) * ((1 - fu) * z00 + fu * z10) + fv * ((1 - fu) * z01 + fu * z11);
    const double gx = ((1 - fv) * (z10 - z00) + fv * (z11 - z01)) / surface.cell;
    const double gy = ((1 - fu) * (z01 - z00) + fu * (z11 - z10)) / surface.cell;
    const double h = double(p.z) - ground;
    if (h >= -config.below_m && h <= config.above_m + config.slope_scale * std::hypot(gx, gy)) {
      result.is_ground[i] = 1;
      ++result.ground_count;
    }
  }
  return result;
}

}  // namespace fieldlidar::segmentation
