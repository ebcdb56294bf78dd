// YAML form of the leg detector config (the seed's feature library as a file's text). Only text
// is handled here: reading and writing files is the caller's job.

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/people/leg_training.hpp"
#include "yaml_fields.hpp"

namespace fieldlidar::people {

namespace {

using yaml_fields::field;

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
  if (!(c.path_min_m < c.path_max_m)) throw Error(source + ": path_min_m must be below path_max_m");
  if (!(c.curve_max > 0)) throw Error(source + ": curve_max must be positive");
  return c;
}

}  // namespace fieldlidar::people
