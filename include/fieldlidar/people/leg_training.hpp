#pragma once
/// \file The seed's "learned feature library": leg bounds estimated from labelled arcs, matching
/// detections against annotations, and the YAML form of LegDetectorConfig.

#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "fieldlidar/people/leg_detector.hpp"

namespace fieldlidar::people {

/// One-to-one matching of detections to truth points within `radius_m` (closest pairs first).
struct MatchCounts {
  std::size_t true_positive = 0, false_positive = 0, false_negative = 0;
  double precision() const;
  double recall() const;
  MatchCounts& operator+=(const MatchCounts& o);
};
/// True when `p` (sensor frame, m) lies in the wedge bearing_min_deg..bearing_max_deg (0 = x
/// forward, counter-clockwise positive) within range_max_m: the region where a dataset annotates
/// every leg, outside which unmatched detections are not scored.
bool in_bearing_wedge(const Eigen::Vector2d& p, double bearing_min_deg, double bearing_max_deg,
                      double range_max_m);

/// One-to-one matching, closest pairs first, within `radius_m`. `matched`, when given, receives
/// one flag per detection (1 = matched to a truth point).
MatchCounts match_points(std::span<const Eigen::Vector2d> detections,
                         std::span<const Eigen::Vector2d> truth, double radius_m,
                         std::vector<char>* matched = nullptr);

/// An arc with its label: a leg when its midpoint is within the match radius of a truth leg.
struct LabelledArc {
  ArcFeatures features;
  bool leg = false;
  bool foreground = true;  ///< 2D: in_foreground() with the config's margin
};

/// 2D: the arcs of one scan (split by jump distance, as detect_legs_2d does), labelled against the
/// annotated leg positions of that scan.
std::vector<LabelledArc> label_arcs_2d(std::span<const Eigen::Vector2d> ordered_points,
                                       std::span<const Eigen::Vector2d> truth_legs,
                                       const LegDetectorConfig& config, double match_radius_m);

/// Distance from each truth leg to the nearest other truth leg of the same scan, when below
/// `max_m` (the two legs of one person).
std::vector<double> leg_pair_distances(std::span<const Eigen::Vector2d> truth_legs,
                                       double max_m = 1.0);

struct TrainingOptions {
  double low_quantile = 0.02;   ///< lower bounds at this quantile of the leg arcs
  double high_quantile = 0.98;  ///< upper bounds at this quantile
  double margin = 0.05;         ///< bounds widened by this fraction
};

struct TrainingResult {
  LegDetectorConfig config;
  std::size_t leg_arcs = 0, other_arcs = 0, leg_pairs = 0;
  /// Share of the other (non-leg) arcs the seed's bounds accept, and with the shape additions
  /// (min points, chord, circle fit, curve min) on.
  double other_accepted_seed = 0, other_accepted_all = 0;
  double leg_accepted_seed = 0, leg_accepted_all = 0;
};

/// Estimates delta_c, L_min, L_max (seed) and min_points, chord_max, radius bounds (additions)
/// from the quantiles of the leg arcs, dist_max from the leg pair distances; other fields are
/// taken from `base`. Throws std::invalid_argument when there are no leg arcs.
TrainingResult estimate_leg_bounds(const std::vector<LabelledArc>& arcs,
                                   const std::vector<double>& pair_distances,
                                   const LegDetectorConfig& base, const TrainingOptions& options);

/// YAML text of a config (every field, units in the comments).
std::string to_yaml(const LegDetectorConfig& config);
/// Parses YAML text onto `base` (absent keys keep their value); throws fieldlidar::Error naming
/// `source` and the key for unknown keys or bad values, and the key and value for a setting out
/// of the detector's range (e.g. range_max_m not above range_min_m > 0, segment_jump_m <= 0,
/// min_points < 1, an even smooth_window or one above 99).
LegDetectorConfig legs_config_from_yaml(const std::string& text, const std::string& source,
                                        const LegDetectorConfig& base = {});

}  // namespace fieldlidar::people
