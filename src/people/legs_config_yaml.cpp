// YAML form of the leg detector config (the seed's feature library as a file's text). Only text
// is handled here: reading and writing files is the caller's job.

#include <numbers>
#include <string>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/people/leg_training.hpp"
#include "yaml_fields.hpp"

namespace fieldlidar::people {

namespace {

using yaml_fields::field;

constexpr int kMaxSmoothWindow = 99;  ///< points
/// More returns than a leg arc holds on any scanner (a 0.1 deg 2D laser sees a 0.15 m leg at
/// 0.3 m as ~290 points).
constexpr int kMaxArcPoints = 10000;

const yaml_fields::Fields<LegDetectorConfig>& legs_fields() {
  using C = LegDetectorConfig;
  static const yaml_fields::Fields<C> f = {
      {"curve_max", field(&C::curve_max, "delta_c: a leg arc has L_k / D_k below this")},
      {"path_min_m", field(&C::path_min_m, "L_min (m)")},
      {"path_max_m", field(&C::path_max_m, "L_max (m)")},
      {"pair_distance_max_m", field(&C::pair_distance_max_m, "dist_max: legs of one person (m)")},
      {"range_min_m", field(&C::range_min_m, "S_s (m)")},
      {"range_max_m", field(&C::range_max_m, "S_m (m)")},
      {"min_rings", field(&C::min_rings, "3D: rings with a leg arc needed for a leg")},
      {"segment_jump_m", field(&C::segment_jump_m, "consecutive points farther apart split (m)")},
      {"leg_merge_radius_m", field(&C::leg_merge_radius_m, "3D: arcs of one leg across rings (m)")},
      {"split_azimuth_gap_rad", field(&C::split_azimuth_gap_rad, "3D: azimuth gap split (rad)")},
      {"path_step_m", field(&C::path_step_m, "L_k over points this far apart (m, 0 = all)")},
      {"smooth_window", field(&C::smooth_window, "moving average before L_k (points, 1 = off)")},
      {"use_min_points", field(&C::use_min_points, "addition: minimum point count")},
      {"min_points", field(&C::min_points, "points per leg arc")},
      {"use_chord_max", field(&C::use_chord_max, "addition: maximum chord")},
      {"chord_max_m", field(&C::chord_max_m, "D_k upper bound (m)")},
      {"use_circle_fit", field(&C::use_circle_fit, "addition: circle-fit radius check")},
      {"radius_min_m", field(&C::radius_min_m, "fitted radius lower bound (m)")},
      {"radius_max_m", field(&C::radius_max_m, "fitted radius upper bound (m)")},
      {"circle_rms_max_m", field(&C::circle_rms_max_m, "fit residual bound (m)")},
      {"use_curve_min", field(&C::use_curve_min, "addition: reject straight arcs")},
      {"curve_min", field(&C::curve_min, "L_k / D_k lower bound")},
      {"use_background", field(&C::use_background, "addition: 2D static background filter")},
      {"use_foreground", field(&C::use_foreground, "addition: 2D arc not seen through a gap")},
      {"foreground_margin_m", field(&C::foreground_margin_m, "neighbour nearer by this (m)")},
      {"classifier_file",
       field(&C::classifier_file, "2D learned leg classifier YAML (relative; empty = bounds)")},
  };
  return f;
}

/// Every value within what the detector can use: outside, it runs and finds nothing (a range_max_m
/// of -5, a segment_jump_m of 0 splitting every point apart, a min_points of 0 that tests nothing)
/// or crawls (a smoothing window of a billion points), with no word of why.
void check_legs(const LegDetectorConfig& c, const std::string& source) {
  auto need = [&](bool ok, const std::string& what) {
    if (!ok) throw Error(source + ": leg detector setting " + what);
  };
  // L_k / D_k >= 1 for any arc (a path is no shorter than its chord): delta_c <= 1 takes none.
  need(c.curve_max > 1, "curve_max " + short_number(c.curve_max) + " must be above 1");
  need(c.path_min_m >= 0 && c.path_min_m < c.path_max_m,
       "path_min_m " + short_number(c.path_min_m) + " must be >= 0 and below path_max_m " +
           short_number(c.path_max_m));
  need(c.pair_distance_max_m > 0,
       "pair_distance_max_m " + short_number(c.pair_distance_max_m) + " must be positive");
  // 0 would keep the zero-range returns scanners report for "no echo".
  need(c.range_min_m > 0, "range_min_m " + short_number(c.range_min_m) + " must be positive");
  need(c.range_max_m > c.range_min_m, "range_max_m " + short_number(c.range_max_m) +
                                          " must be above range_min_m " +
                                          short_number(c.range_min_m));
  need(c.min_rings >= 1, "min_rings " + std::to_string(c.min_rings) + " must be at least 1");
  need(c.segment_jump_m > 0,
       "segment_jump_m " + short_number(c.segment_jump_m) + " must be positive");
  need(c.leg_merge_radius_m > 0,
       "leg_merge_radius_m " + short_number(c.leg_merge_radius_m) + " must be positive");
  need(c.split_azimuth_gap_rad >= 0 && c.split_azimuth_gap_rad <= 2 * std::numbers::pi,
       "split_azimuth_gap_rad " + short_number(c.split_azimuth_gap_rad) + " must lie in [0, 2 pi]");
  need(c.path_step_m >= 0, "path_step_m " + short_number(c.path_step_m) + " must not be negative");
  // Centred on each point, so odd; a leg arc holds tens of returns, so a window of a hundred
  // already averages it flat.
  need(c.smooth_window >= 1 && c.smooth_window <= kMaxSmoothWindow && c.smooth_window % 2 == 1,
       "smooth_window " + std::to_string(c.smooth_window) + " must be an odd number in [1, " +
           std::to_string(kMaxSmoothWindow) + "]");
  need(c.min_points >= 1 && c.min_points <= kMaxArcPoints,
       "min_points " + std::to_string(c.min_points) + " must lie in [1, " +
           std::to_string(kMaxArcPoints) + "]");
  need(c.chord_max_m > 0, "chord_max_m " + short_number(c.chord_max_m) + " must be positive");
  // The bounds of an addition that is off are not read: only their sign is checked, so that a
  // file may switch a test off without tending its bounds.
  need(c.radius_min_m >= 0 && c.radius_max_m > 0,
       "radius_min_m " + short_number(c.radius_min_m) + " and radius_max_m " +
           short_number(c.radius_max_m) + " must be >= 0 and positive");
  need(!c.use_circle_fit || c.radius_min_m < c.radius_max_m,
       "radius_min_m " + short_number(c.radius_min_m) + " must be below radius_max_m " +
           short_number(c.radius_max_m) + " (use_circle_fit)");
  need(c.circle_rms_max_m > 0,
       "circle_rms_max_m " + short_number(c.circle_rms_max_m) + " must be positive");
  need(c.curve_min >= 0, "curve_min " + short_number(c.curve_min) + " must not be negative");
  need(!c.use_curve_min || c.curve_min < c.curve_max,
       "curve_min " + short_number(c.curve_min) + " must be below curve_max " +
           short_number(c.curve_max) + " (use_curve_min)");
  need(c.foreground_margin_m >= 0,
       "foreground_margin_m " + short_number(c.foreground_margin_m) + " must not be negative");
}

}  // namespace

std::string to_yaml(const LegDetectorConfig& c) {
  return "# fieldlidar leg detector (seed 000 feature library)\n" +
         yaml_fields::print(legs_fields(), c, "legs");
}

LegDetectorConfig legs_config_from_yaml(const std::string& text, const std::string& source,
                                        const LegDetectorConfig& base) {
  LegDetectorConfig c = base;
  const YAML::Node root = yaml_fields::load(text, source);
  // A file of settings for the legs alone may hold them at its root; the person tracker's
  // `tracker:` map beside them is read by joint_tracker_config_from_yaml.
  if (root.IsMap() && root["legs"])
    yaml_fields::parse(legs_fields(), root["legs"], c, source, "leg detector");
  else
    yaml_fields::parse(legs_fields(), root, c, source, "leg detector", {"tracker"});
  check_legs(c, source);
  return c;
}

}  // namespace fieldlidar::people
