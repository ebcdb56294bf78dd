#pragma once
/// \file Planar poses and paths of a ground robot (map frame, metres, radians).

#include <cstddef>
#include <vector>

#include "fieldlidar/core/pose2.hpp"

namespace fieldlidar::planning {

using fieldlidar::Pose2;
using fieldlidar::wrap_angle;

/// One sample of a planned path; `reverse` when the robot drives backwards on the way to it.
struct PathPose {
  Pose2 pose;
  bool reverse = false;
};

using Path = std::vector<PathPose>;

/// Length (m) of the polyline through the path's positions.
double path_length_m(const Path& path);

/// Menger curvature (1/m) at sample i (circle through samples i-1, i, i+1; 0 at the ends and
/// where the three coincide or the direction of travel changes).
double menger_curvature(const Path& path, std::size_t i);

/// Largest Menger curvature (1/m) over the path.
double max_curvature(const Path& path);

/// Sum of |heading change| (rad) between consecutive samples: how much the path turns.
double total_turning_rad(const Path& path);

/// Number of changes between forward and reverse driving.
int direction_changes(const Path& path);

}  // namespace fieldlidar::planning
