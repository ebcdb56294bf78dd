#pragma once
// The map `fieldlidar plan --map` reads: a nav2 map_server map (YAML + PGM, tau quantised to 8
// bits) or the traversability command's own GeoTIFF layers (full precision, with the impassable
// and points layers that tell blocked and unseen cells apart).

#include <filesystem>
#include <string>
#include <vector>

#include "fieldlidar/core/grid2d.hpp"

namespace fieldlidar::app {

struct PlanMap {
  Grid2D grid;                               ///< layer kTraversability, + kImpassable, kPoints
  std::string format;                        ///< "nav2" or "geotiff"
  std::vector<std::filesystem::path> files;  ///< every file read (never overwritten)
};

/// `map` is a nav2 YAML, a folder holding traversability.yaml (or one .yaml), a folder holding
/// traversability.tif (e.g. the traversability command's DIR/layers), or that .tif itself; beside
/// a traversability GeoTIFF, impassable.tif and points.tif are read when present and must cover
/// the same cells. Throws fieldlidar::Error naming the path and the problem.
PlanMap read_plan_map(const std::string& map);

}  // namespace fieldlidar::app
