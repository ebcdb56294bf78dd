#pragma once
// `fieldlidar trunks --truth`: the simulator's trees.csv and detection scores against it.

#include <filesystem>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "fieldlidar/core/pose.hpp"
#include "fieldlidar/forest/trunks.hpp"

namespace fieldlidar::app {

/// A true tree of the simulator's trees.csv: axis point at 1.3 m and DBH.
struct TrueTree {
  Eigen::Vector3d at_dbh;
  double dbh_m;
};

/// The rows of a simulator trees.csv (id,base_x_m,base_y_m,base_z_m,axis_x,axis_y,axis_z,dbh_m,
/// ...) in the file's own (world) frame. Raises Error naming the file, and the line and column
/// where there is one, for a file that cannot be read or holds no tree, a value that is not a
/// finite number, an axis that does not point up or a DBH that is not positive.
std::vector<TrueTree> read_true_trees(const std::filesystem::path& path);

/// `trees` moved by `T_frame_world` (into a scan's frame, or a plot's recentred coordinates).
std::vector<TrueTree> moved(const std::vector<TrueTree>& trees, const Pose& T_frame_world);

/// Prints detection scores of `trees` against the truth; with a path, only trees within
/// `radius_m` of it count (and detections farther than `radius_m` + 0.5 m are not scored). A
/// match lies within 0.3 m at 1.3 m.
void print_trunk_scores(const std::vector<forest::Tree>& trees, const std::vector<TrueTree>& truth,
                        const std::vector<Eigen::Vector3d>& path, double radius_m = 10.0);

/// The simulator's pose of a scan written as `<folder>/pcd/<index>.pcd` (world from sensor, from
/// `<folder>/poses.txt`), or nothing when the scan does not lie in a simulator folder.
std::optional<Pose> simulator_scan_pose(const std::filesystem::path& scan);

}  // namespace fieldlidar::app
