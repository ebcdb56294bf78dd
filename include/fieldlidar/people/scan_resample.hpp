#pragma once
/// \file A 2D scan seen at another angular step: the leg classifier's features (point count,
/// spacing, angular width) are those of the laser it was trained on, so a coarser laser's scans
/// are resampled to that step before their segments are scored (LegPipeline2D).

#include <span>
#include <vector>

#include <Eigen/Core>

namespace fieldlidar::people {

/// The angular step of a scan (rad): the lower quartile of the bearing differences between
/// consecutive points (sensor at the origin, beam order) that are positive and under 0.1 rad
/// (gaps of missing beams and the wrap of a full turn left out); 0 when fewer than 10 pairs.
double scan_step_rad(std::span<const Eigen::Vector2d> points);

/// `points` (beam order, finite) at a uniform angular step of about `step_rad`: each run of
/// consecutive points closer than `jump_m` to their neighbour (one surface) is replaced by
/// samples evenly spaced in bearing over the run's bearings, round(extent / step_rad) + 1 of
/// them, the range interpolated linearly in bearing between the two points around each sample;
/// the run's first and last points are kept as they are, and so is a point alone. Nothing is
/// added across a jump (a gap between surfaces stays a gap).
std::vector<Eigen::Vector2d> resample_scan(std::span<const Eigen::Vector2d> points, double step_rad,
                                           double jump_m);

}  // namespace fieldlidar::people
