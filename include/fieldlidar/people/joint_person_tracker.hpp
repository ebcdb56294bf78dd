#pragma once
/// \file Joint tracking of a person's two legs (after Leigh et al., "Person tracking and following
/// with 2D laser scanners", ICRA 2015): one Kalman filter per person, updated by the pair of its
/// legs or, when one leg hides behind the other or both merge into one segment, by the one leg
/// seen. A person's confidence is the decayed sum of its legs' classifier scores. A track is
/// reported once confident and either walking (it has moved `min_travel_m` from where it was
/// born) or standing in the follow zone in front of the sensor for `zone_confirm_hits` paired
/// detections (an operator who stands in front of the mower is chosen before walking off).
/// Space that a static background grid calls occupied (furniture, trunks, posts) holds no
/// track: no birth there, and a track that stays there is dropped.
///
/// The same tracker serves 2D scans (LegPipeline2D) and the legs of 3D sweeps: legs come in the
/// fixed frame with a score (classifier score minus its threshold; shape tests: +1 when passed).
/// Positions in m, times in s.

#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <vector>

#include <Eigen/Geometry>

#include "fieldlidar/people/static_background.hpp"
#include "fieldlidar/people/tracker.hpp"

namespace fieldlidar::people {

struct JointTrackerConfig {
  double pair_distance_max_m = 0.6;  ///< two legs closer than this can be one person's (m)
  double gate_m = 0.55;              ///< a pair or leg this near a person's prediction updates it
  /// A pair is preferred over one of its legs unless its midpoint is this much farther from the
  /// prediction (m): a track fed one leg sits on that leg, half a stride off its body.
  double pair_bonus_m = 0.3;
  double accel_sigma_m_s2 = 2.0;  ///< white-noise acceleration of a person
  double pair_sigma_m = 0.07;     ///< measurement noise of a pair's midpoint (m)
  double single_sigma_m = 0.15;   ///< of a single leg standing for the person (m)
  double max_speed_m_s = 2.5;
  /// Confidence: c <- decay * c + min(score, score_cap) summed over the person's legs this scan
  /// (a single leg counts `single_weight` times its score); a track without legs decays.
  double evidence_decay = 0.8;
  double score_cap = 2.0;
  /// Subtracted from every leg score before it adds to a person's confidence: legs that pass the
  /// classifier only just (leg-shaped clutter) do not build up a person.
  double score_offset = 0.0;
  double single_weight = 0.6;
  /// Births: an unused pair with a positive score sum; a single unused leg with at least this
  /// score (both legs merged into one segment, or one hidden).
  double single_birth_score_min = 1.0;
  /// Reporting: confidence, detections and walked distance needed (m).
  double confirm_evidence = 2.0;
  int confirm_hits = 4;
  double min_travel_m = 1.0;
  /// A track that does not walk is reported after this many paired detections anywhere
  /// (0 = never; a single leg-shaped post does not pair) that have a standing person's shape:
  /// both legs no wider than `standing_leg_width_max_m` (LegObservation::width_m, the end points
  /// of its segment) and their centres at most `standing_pair_distance_max_m` apart (a person
  /// standing keeps the feet within a shoulder's width; a chair's or a table's legs stand
  /// farther apart, and boxes and bins pass the classifier as wide blobs). Bounds from a
  /// body's size, not fitted: on negative_2.bag 0.15-0.2 m / 0.4-0.45 m (and no distance bound
  /// with the width bound) all take /right_scan's false persons per scan from 0.028 to 0;
  /// general_tracking_moving_1.bag and positive_1..4 leg recall unchanged.
  int standing_pair_hits = 3;
  double standing_leg_width_max_m = 0.2;
  double standing_pair_distance_max_m = 0.45;
  /// A track is also reported, paired or not, once its confidence reaches this (a person seen
  /// side-on shows one segment for both legs).
  double strong_evidence = 5.0;
  /// The follow zone: range and half angle about the sensor's x axis (m, deg); a track whose
  /// paired detections there reach `zone_confirm_hits` is reported without walking.
  double zone_range_min_m = 0.3;
  double zone_range_max_m = 3.0;
  double zone_half_angle_deg = 40.0;
  int zone_confirm_hits = 8;
  double tentative_max_miss_s = 0.35;  ///< a track not yet reported dies after missing this long
  double delete_after_miss_s = 1.0;    ///< a reported track dies after missing this long
  /// A reported track is still reported this long after its last detection (s).
  double report_coast_s = 0.3;
  /// A track that is not reported dies when its confidence falls below this.
  double evidence_min = -3.0;
  /// No track is born this near an existing one (m).
  double birth_min_separation_m = 0.45;
  /// Consecutive scans on occupied cells after which a track is dropped.
  int occupied_max_scans = 3;
  /// A reported track updated in a scan by a leg scoring at least this is not on occupied space
  /// in that scan (inf: off; LegPipeline2D sets its occupied-space score margin, see
  /// LegPipeline2DConfig::sure_leg_radius_m).
  double occupied_keep_score = std::numeric_limits<double>::infinity();
  /// A reported person updated by carried legs alone (LegObservation::carry_only) for longer
  /// than this is dropped (s): they keep a person followed out of the classifier's reach, not
  /// a track left on clutter.
  double carried_max_s = 4.0;
};

/// True when `sensor_point` (sensor frame, m) lies in the config's follow zone.
bool in_follow_zone(const JointTrackerConfig& c, const Eigen::Vector2d& sensor_point);

/// A leg of this scan, fixed frame.
struct LegObservation {
  Eigen::Vector2d position_m = Eigen::Vector2d::Zero();
  double score = 1.0;    ///< > 0: a leg by this scan alone (classifier score minus its threshold)
  double width_m = 0.0;  ///< distance between the end points of its segment (0 = unknown)
  /// A leg-sized segment the classifier did not take, near a reported person: it may update a
  /// reported person (never another track, never a birth) and adds no confidence.
  bool carry_only = false;
};

struct JointTrack {
  std::uint32_t id = 0;
  Track filter;  ///< position and velocity (Track::id = id)
  double evidence = 0;
  int hits = 0, pair_hits = 0, zone_pair_hits = 0;
  int standing_pair_hits = 0;  ///< paired detections with a standing person's shape
  int occupied_scans = 0;
  double scored_s = 0;  ///< last update by a leg the classifier took (s)
  Eigen::Vector2d born_m = Eigen::Vector2d::Zero();
  double travel_m = 0;  ///< farthest distance from born_m so far
  bool reported = false;
  int legs_now = 0;           ///< legs that updated it this scan (0, 1, 2)
  bool sure_leg_now = false;  ///< one of them scored at least occupied_keep_score
  Eigen::Vector2d position() const { return filter.position(); }
};

struct JointUpdate {
  std::vector<std::int64_t> person_of_leg;  ///< per leg: the person track it updated, or -1
  std::vector<std::uint32_t> reported;      ///< ids of the reported tracks seen this scan
};

class JointPersonTracker {
 public:
  explicit JointPersonTracker(const JointTrackerConfig& config = {});
  /// One scan: `legs` in the fixed frame, `sensor_pose` sensor -> fixed frame (for the follow
  /// zone), `occupied` the static background (nullptr = none). Stamps must not decrease.
  JointUpdate update(double stamp_s, std::span<const LegObservation> legs,
                     const Eigen::Isometry2d& sensor_pose,
                     const StaticBackground* occupied = nullptr);
  const std::vector<JointTrack>& tracks() const { return tracks_; }
  const JointTrack* find(std::uint32_t id) const;
  const JointTrackerConfig& config() const { return config_; }

 private:
  JointTrackerConfig config_;
  std::vector<JointTrack> tracks_;
  std::uint32_t next_id_ = 1;
  double stamp_s_ = 0;
  bool started_ = false;
};

}  // namespace fieldlidar::people
