#include "fieldlidar/io/nav2_map.hpp"

#include <algorithm>
#include <cmath>

#include <sstream>

#include "fieldlidar/core/error.hpp"

namespace fieldlidar::io {
namespace {

unsigned char pixel_of(float tau, const Nav2MapConfig& config, bool scale) {
  if (!std::isfinite(tau)) return kNav2Unknown;
  const double t = std::clamp(double(tau), 0.0, 1.0);
  if (!scale) return 1.0 - t > config.occupied_thresh ? kNav2Occupied : kNav2Free;
  auto p = static_cast<unsigned char>(std::lround(254.0 * t));
  // A known cell never takes the unknown grey.
  if (p == kNav2Unknown) p = kNav2Unknown + 1;
  return p;
}

}  // namespace

Nav2Map encode_nav2_map(const Grid2D& grid, const std::string& tau_layer,
                        const std::string& image_name, const Nav2MapConfig& config) {
  const GridGeometry& g = grid.geometry();
  if (!grid.has_layer(tau_layer))
    throw Error("nav2 map: the grid has no layer '" + tau_layer + "'");
  if (g.width <= 0 || g.height <= 0)
    throw Error("nav2 map: empty grid (" + std::to_string(g.width) + " x " +
                std::to_string(g.height) + " cells)");
  if (config.mode != "trinary" && config.mode != "scale")
    throw Error("nav2 map: mode '" + config.mode + "' is not trinary or scale");
  if (!(config.free_thresh > 0 && config.free_thresh < config.occupied_thresh &&
        config.occupied_thresh < 1))
    throw Error("nav2 map: thresholds free " + std::to_string(config.free_thresh) + ", occupied " +
                std::to_string(config.occupied_thresh) + ": not 0 < free < occupied < 1");
  const bool scale = config.mode == "scale";
  const std::span<const float> tau = grid.layer(tau_layer);
  Nav2Map map;
  std::ostringstream head;
  head.precision(10);
  head << "P5\n# fieldlidar traversability, " << g.resolution_m << " m cells\n"
       << g.width << ' ' << g.height << "\n255\n";
  map.pgm = head.str();
  const std::size_t header = map.pgm.size();
  map.pgm.resize(header + g.cell_count());
  for (int row = 0; row < g.height; ++row) {
    const int iy = g.height - 1 - row;  // image row 0 is the top: the largest y
    for (int ix = 0; ix < g.width; ++ix)
      map.pgm[header + std::size_t(row) * g.width + ix] =
          static_cast<char>(pixel_of(tau[g.linear_index(ix, iy)], config, scale));
  }
  std::ostringstream y;
  y.precision(10);
  y << "image: " << image_name << "\nmode: " << config.mode << "\nresolution: " << g.resolution_m
    << "\norigin: [" << g.origin_m.x() << ", " << g.origin_m.y() << ", 0.0]\nnegate: 0\n"
    << "occupied_thresh: " << config.occupied_thresh << "\nfree_thresh: " << config.free_thresh
    << "\n";
  map.yaml = y.str();
  return map;
}

}  // namespace fieldlidar::io
