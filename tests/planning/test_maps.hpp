#pragma once
// Hand-built traversability maps for the planner's tests.

#include <cmath>
#include <limits>
#include <random>

#include "fieldlidar/core/grid2d.hpp"
#include "fieldlidar/terrain/traversability.hpp"

namespace fieldlidar::planning::test {

namespace L = terrain::layer;

/// w x h m of 0.5 m cells, origin (0, 0), tau 1 everywhere, nothing impassable.
inline Grid2D open_map(double w_m, double h_m, double res = 0.5) {
  GridGeometry g;
  g.resolution_m = res;
  g.width = int(std::lround(w_m / res));
  g.height = int(std::lround(h_m / res));
  Grid2D map(g);
  map.add_layer(L::kTraversability, 1.0f);
  map.add_layer(L::kImpassable, 0.0f);
  map.add_layer(L::kPoints, 10.0f);
  return map;
}

/// Marks [x0, x1] x [y0, y1] (m) impassable (tau 0).
inline void block(Grid2D& map, double x0, double y0, double x1, double y1) {
  const GridGeometry& g = map.geometry();
  for (int iy = 0; iy < g.height; ++iy)
    for (int ix = 0; ix < g.width; ++ix) {
      const Eigen::Vector2d c = g.cell_center(ix, iy);
      if (c.x() >= x0 && c.x() <= x1 && c.y() >= y0 && c.y() <= y1) {
        map.at(L::kTraversability, ix, iy) = 0.0f;
        map.at(L::kImpassable, ix, iy) = 1.0f;
      }
    }
}

/// A random field: tau in [0.3, 1], `blobs` impassable discs and rectangles.
inline Grid2D random_map(std::mt19937& rng, double w_m, double h_m, int blobs) {
  Grid2D map = open_map(w_m, h_m);
  std::uniform_real_distribution<double> ux(0.0, w_m), uy(0.0, h_m), tau(0.3, 1.0), size(0.5, 4.0);
  const GridGeometry& g = map.geometry();
  auto t = map.layer(L::kTraversability);
  for (auto& v : t) v = float(tau(rng));
  for (int b = 0; b < blobs; ++b) {
    const double cx = ux(rng), cy = uy(rng), r = size(rng);
    if (b % 2) {
      block(map, cx - r, cy - 0.3 * r, cx + r, cy + 0.3 * r);
      continue;
    }
    for (int iy = 0; iy < g.height; ++iy)
      for (int ix = 0; ix < g.width; ++ix)
        if ((g.cell_center(ix, iy) - Eigen::Vector2d(cx, cy)).norm() < r) {
          map.at(L::kTraversability, ix, iy) = 0.0f;
          map.at(L::kImpassable, ix, iy) = 1.0f;
        }
  }
  return map;
}

}  // namespace fieldlidar::planning::test
