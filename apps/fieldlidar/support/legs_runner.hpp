#pragma once
// Legs and tracked persons frame by frame, as `fieldlidar legs` finds them: 2D scans through
// people::LegPipeline2D (the shipped config and its learned classifier by default), 3D sweeps
// through the follow pipeline's perception and a PersonTracker in the sensor frame. Shared by
// the commands that run the detector (legs, eval-tracking).

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "fieldlidar/core/sensor_model.hpp"
#include "fieldlidar/follow/pipeline.hpp"
#include "fieldlidar/io/frame_source.hpp"
#include "fieldlidar/people/legs_2d_pipeline.hpp"
#include "fieldlidar/people/tracker.hpp"
#include "support/frame_clock.hpp"

namespace fieldlidar::app {

struct LegsRunOptions {
  std::string input;   ///< named in errors
  std::string config;  ///< leg detector YAML; "" = the shipped legs_2d.yaml for 2D scans
  std::string sensor;  ///< sensor preset for 3D input without sensor metadata
  bool seed_only = false;
  bool still = false;  ///< 2D: no ego-motion estimation by scan matching
  bool no_classifier = false;
  /// 2D: LegPipeline2DConfig::compact_occupancy_weight (0..1).
  double compact_occupancy = 1.0;
  /// 2D: LegPipeline2DConfig::occupied_leg_score_min / occupied_leg_evidence_min (empty: the
  /// defaults, tuned for the shipped classifier's score scale).
  std::vector<double> occupied_leg;
  /// 2D: trace what became of every scan segment (FrameLegsPeople::segments).
  bool trace_segments = false;
};

/// One frame's legs and reported persons (sensor frame, m) with the persons' track ids.
struct FrameLegsPeople {
  std::vector<Eigen::Vector2d> legs;
  std::vector<Eigen::Vector2d> persons;
  std::vector<std::int64_t> person_ids;
  /// 2D with LegsRunOptions::trace_segments: every segment of the scan and what became of it.
  std::vector<people::SegmentTrace> segments;
};

class LegsRunner {
 public:
  /// Loads the detector config (and its classifier); throws fieldlidar::Error when a file is
  /// missing or malformed.
  explicit LegsRunner(const LegsRunOptions& options);
  /// One frame of `source` (which gives the sensor model of 3D frames). `T_fixed_sensor`, the
  /// sensor's pose from recorded odometry, places 2D scans instead of the pipeline's own scan
  /// matching (3D sweeps are tracked in the sensor frame either way).
  FrameLegsPeople process(const io::Frame& frame, const io::FrameSource& source,
                          const std::optional<Pose>& T_fixed_sensor = std::nullopt);
  /// True once a 2D scan was processed.
  bool scans_2d() const { return scans_2d_ > 0; }
  /// The 2D leg pipeline's config as loaded (detector, classifier); throws fieldlidar::Error
  /// when the shipped config is missing and was needed.
  const people::LegPipeline2DConfig& config_2d() const;
  /// "2D detector <config>, classifier <file>" for the report, and how many scans were
  /// resampled to the classifier's angular step (a coarser laser than it learned).
  std::string detector_summary() const;

 private:
  LegsRunOptions options_;
  people::LegDetectorConfig legs_;
  std::string missing_config_;  ///< the 2D default config that was not found
  std::string config_path_, classifier_path_;
  std::unique_ptr<people::LegPipeline2D> pipeline_;
  people::PersonTracker tracker_;
  follow::FollowConfig follow_cfg_;
  std::optional<SensorModel> sensor_;
  bool level_warned_ = false;  ///< 3D: a tilted sweep was said (support/sweep_levelling)
  FrameClock clock_;
  std::size_t scans_2d_ = 0, resampled_ = 0;  ///< 2D scans processed, and those resampled
};

}  // namespace fieldlidar::app
