// YAML form of the joint person tracker's settings (the `tracker:` map of a leg detector file).

#include "fieldlidar/people/joint_tracker_yaml.hpp"

#include "fieldlidar/core/error.hpp"
#include "yaml_fields.hpp"

namespace fieldlidar::people {

namespace {

using yaml_fields::field;

const yaml_fields::Fields<JointTrackerConfig>& tracker_fields() {
  using C = JointTrackerConfig;
  static const yaml_fields::Fields<C> f = {
      {"pair_distance_max_m", field(&C::pair_distance_max_m, "two legs of one person (m)")},
      {"gate_m", field(&C::gate_m, "a pair or leg this near a prediction updates it (m)")},
      {"pair_bonus_m", field(&C::pair_bonus_m, "a pair preferred over one leg by (m)")},
      {"accel_sigma_m_s2", field(&C::accel_sigma_m_s2, "white-noise acceleration (m/s^2)")},
      {"pair_sigma_m", field(&C::pair_sigma_m, "noise of a pair's midpoint (m)")},
      {"single_sigma_m", field(&C::single_sigma_m, "noise of one leg for the person (m)")},
      {"max_speed_m_s", field(&C::max_speed_m_s, "fastest person (m/s)")},
      {"evidence_decay", field(&C::evidence_decay, "confidence kept per scan (0..1)")},
      {"score_cap", field(&C::score_cap, "largest leg score added per scan")},
      {"score_offset", field(&C::score_offset, "subtracted from every leg score")},
      {"single_weight", field(&C::single_weight, "a single leg's score counts this much")},
      {"single_birth_score_min",
       field(&C::single_birth_score_min, "score a lone leg needs to start a track")},
      {"confirm_evidence", field(&C::confirm_evidence, "confidence needed to report")},
      {"confirm_hits", field(&C::confirm_hits, "detections needed to report")},
      {"min_travel_m", field(&C::min_travel_m, "walked distance that reports a track (m)")},
      {"standing_pair_hits",
       field(&C::standing_pair_hits, "standing-shaped pairs that report (0 = never)")},
      {"standing_leg_width_max_m",
       field(&C::standing_leg_width_max_m, "widest leg of a standing pair (m)")},
      {"standing_pair_distance_max_m",
       field(&C::standing_pair_distance_max_m, "widest stance of a standing pair (m)")},
      {"strong_evidence", field(&C::strong_evidence, "confidence that reports any track")},
      {"zone_range_min_m", field(&C::zone_range_min_m, "follow zone, near range (m)")},
      {"zone_range_max_m", field(&C::zone_range_max_m, "follow zone, far range (m)")},
      {"zone_half_angle_deg", field(&C::zone_half_angle_deg, "follow zone half angle (deg)")},
      {"zone_confirm_hits", field(&C::zone_confirm_hits, "pairs in the zone that report")},
      {"tentative_max_miss_s",
       field(&C::tentative_max_miss_s, "an unreported track dies unseen after (s)")},
      {"delete_after_miss_s", field(&C::delete_after_miss_s, "a reported track dies after (s)")},
      {"report_coast_s", field(&C::report_coast_s, "reported this long after its last leg (s)")},
      {"evidence_min", field(&C::evidence_min, "an unreported track dies below this")},
      {"birth_min_separation_m",
       field(&C::birth_min_separation_m, "no track born this near another (m)")},
      {"occupied_max_scans",
       field(&C::occupied_max_scans, "scans on occupied space before a track is dropped")},
  };
  return f;
}

void check_tracker(const JointTrackerConfig& c, const std::string& source) {
  auto need = [&](bool ok, const char* what) {
    if (!ok) throw Error(source + ": tracker setting " + what);
  };
  need(c.pair_distance_max_m > 0, "pair_distance_max_m must be positive");
  need(c.gate_m > 0, "gate_m must be positive");
  need(c.accel_sigma_m_s2 > 0, "accel_sigma_m_s2 must be positive");
  need(c.pair_sigma_m > 0 && c.single_sigma_m > 0,
       "pair_sigma_m and single_sigma_m must be positive");
  need(c.max_speed_m_s > 0, "max_speed_m_s must be positive");
  need(c.evidence_decay > 0 && c.evidence_decay < 1, "evidence_decay must lie in (0, 1)");
  need(c.score_cap > 0, "score_cap must be positive");
  need(c.single_weight >= 0, "single_weight must not be negative");
  need(c.confirm_hits >= 1, "confirm_hits must be at least 1");
  need(c.min_travel_m >= 0, "min_travel_m must not be negative");
  need(c.standing_pair_hits >= 0 && c.zone_confirm_hits >= 0 && c.occupied_max_scans >= 0,
       "standing_pair_hits, zone_confirm_hits and occupied_max_scans must not be negative");
  need(c.zone_range_min_m >= 0 && c.zone_range_max_m > c.zone_range_min_m,
       "zone_range_max_m must lie beyond zone_range_min_m (>= 0)");
  need(c.zone_half_angle_deg > 0 && c.zone_half_angle_deg <= 180,
       "zone_half_angle_deg must lie in (0, 180]");
  need(c.tentative_max_miss_s >= 0 && c.delete_after_miss_s >= 0 && c.report_coast_s >= 0,
       "tentative_max_miss_s, delete_after_miss_s and report_coast_s must not be negative");
  need(c.birth_min_separation_m >= 0, "birth_min_separation_m must not be negative");
}

}  // namespace

std::string to_yaml(const JointTrackerConfig& c) {
  return "# person tracker (legs tracked jointly; confidence from the legs' scores)\n" +
         yaml_fields::print(tracker_fields(), c, "tracker");
}

JointTrackerConfig joint_tracker_config_from_yaml(const std::string& text,
                                                  const std::string& source,
                                                  const JointTrackerConfig& base) {
  JointTrackerConfig c = base;
  const YAML::Node root = yaml_fields::load(text, source);
  if (!root.IsMap() || !root["tracker"]) return c;
  yaml_fields::parse(tracker_fields(), root["tracker"], c, source, "tracker");
  check_tracker(c, source);
  return c;
}

}  // namespace fieldlidar::people
