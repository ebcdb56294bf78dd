#pragma once
// The files of `fieldlidar trunks`: trees.csv, trees.geojson and the top-down pictures (the stems
// of one scan or plot over its points; a sequence's trunk map over the driven path).

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "fieldlidar/core/point_cloud.hpp"
#include "fieldlidar/forest/trunks.hpp"

namespace fieldlidar::app {

/// trees.csv, bases moved by `origin` (a plot file's own coordinates); dbh_m is empty for a stem
/// marked dbh_uncertain (its diameter a guess no scan line measured).
std::string trees_csv(const std::vector<forest::Tree>& trees, const Eigen::Vector3d& origin);
/// trees.geojson: one Point feature per tree with its quality record (dbh_m null where
/// dbh_uncertain).
std::string trees_geojson(const std::vector<forest::Tree>& trees, const Eigen::Vector3d& origin);

/// A stem slice's picture: every point of the slice, each stem's circle with its id.
void draw_slice(const PointCloud& cloud, const std::vector<forest::Tree>& trees,
                const std::filesystem::path& path, bool force);
/// Top-down: every point faint, the 1.2-1.4 m slice above the ground dark, the DBH circles.
void draw_trees(const PointCloud& cloud, const std::vector<std::uint8_t>& ground,
                const std::vector<forest::Tree>& trees, const std::filesystem::path& path,
                bool force);
/// Top-down: the trunk map's DBH circles with ids over the driven path.
void draw_trunk_map(const std::vector<forest::Tree>& trees,
                    const std::vector<Eigen::Vector3d>& path, const std::filesystem::path& file,
                    bool force);

}  // namespace fieldlidar::app
