#pragma once
/// \file Seed 004, f42: conjugate-gradient smoothing of a Hybrid A* path (Dolgov et al. 2010:
/// obstacle, smoothness and curvature terms), never onto blocked cells nor above max curvature.

#include "fieldlidar/planning/pose2.hpp"

namespace fieldlidar::planning {

class PlanningMap;

struct SmoothingConfig {
  double weight_obstacle = 0.1;      ///< w_o on (d_max - d)^2 where the distance d < d_max
  double obstacle_distance_m = 0.8;  ///< d_max (to the nearest blocked cell centre)
  double weight_smoothness = 4.0;    ///< w_s on |x_{i+1} - 2 x_i + x_{i-1}|^2
  double weight_curvature = 200.0;   ///< w_k on (kappa - k_t)^2 where kappa > k_t
  /// k_t = share * kappa_max: the term pulls below the bound so small overshoots are rare
  double curvature_target_share = 0.8;
  /// The smoothed path must not cost more: sum of length * (1 + tau_weight * (1 - tau)) (the
  /// planner sets it to its own tau_weight).
  double tau_weight = 2.0;
  int max_iterations = 100;  ///< per forward or reverse run
  /// The optimised vertices are this far apart along the path; the samples in between follow
  /// them by a Catmull–Rom spline of the vertices' displacements.
  double vertex_spacing_m = 0.5;
};

/// How much the smoothing changed the path.
struct SmoothingReport {
  double length_before_m = 0.0, length_after_m = 0.0;
  double turning_before_rad = 0.0, turning_after_rad = 0.0;  ///< total |heading change|
  double max_curvature_after = 0.0;                          ///< 1/m
  double blend = 0.0;  ///< mean share of the vertices' smoothed displacement kept (1 = all;
                       ///< less where it would have touched a blocked cell or bent too much)
  int iterations = 0;
};

/// Smooths `path` (fixed ends and cusps; each forward or reverse run on its own), keeps the
/// largest share of the displacement for which every sample's footprint is free on `map` and the
/// curvature stays <= kappa_max_per_m; headings are re-derived from the smoothed positions.
Path smooth_path(const Path& path, const PlanningMap& map, double kappa_max_per_m,
                 const SmoothingConfig& config, SmoothingReport* report = nullptr);

}  // namespace fieldlidar::planning
