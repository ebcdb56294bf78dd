#include "support/legs_runner.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <fmt/core.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/core/pose2.hpp"
#include "fieldlidar/follow/replay.hpp"
#include "fieldlidar/people/joint_tracker_yaml.hpp"
#include "fieldlidar/people/leg_training.hpp"
#include "support/shipped_data.hpp"
#include "support/sweep_levelling.hpp"

namespace fieldlidar::app {

namespace {

namespace fs = std::filesystem;

/// The shipped 2D config (with its learned classifier): legs_2d.yaml of shipped_config_dirs().
/// Missing, it is an error naming the folders searched (leg recall drops a lot without the
/// classifier), unless --no-classifier or --seed-only ask for the shape tests only.
std::string default_2d_config(bool no_classifier, std::string& missing) {
  if (const auto p = find_shipped_config("legs_2d.yaml")) return p->string();
  if (no_classifier) return {};
  std::string searched;
  for (const auto& d : shipped_config_dirs())
    searched += (searched.empty() ? "" : ", ") + d.string();
  missing = "the shipped leg classifier config legs_2d.yaml is not in " +
            (searched.empty() ? std::string("any known folder") : searched) +
            " (a broken install?): give --config FILE, or --no-classifier to detect legs by "
            "their shape only";
  return {};
}

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  if (!in) throw Error(p.string() + ": cannot be read");
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace

LegsRunner::LegsRunner(const LegsRunOptions& o)
    : options_(o),
      legs_(people::default_2d_legs()),
      tracker_([] {
        people::TrackerConfig tc;
        tc.gate_max_m = 0.8;
        return tc;
      }()),
      clock_(o.input,
             "a folder of frames takes its clock from a KITTI-style times.txt in or beside it "
             "(`legs --rate HZ` stamps frames without one)") {
  config_path_ = o.config.empty()
                     ? default_2d_config(o.no_classifier || o.seed_only, missing_config_)
                     : o.config;
  std::string config_text;
  if (!config_path_.empty()) {
    config_text = read_text(config_path_);
    legs_ = people::legs_config_from_yaml(config_text, config_path_, legs_);
    if (o.no_classifier) legs_.classifier_file.clear();
    if (!legs_.classifier_file.empty()) {
      // The learned classifier lives next to the config (legs-train writes both).
      fs::path model(legs_.classifier_file);
      if (model.is_relative()) model = fs::path(config_path_).parent_path() / model;
      legs_.classifier = std::make_shared<const people::LegClassifier>(
          people::leg_classifier_from_yaml(read_text(model), model.string()));
      classifier_path_ = model.string();
    }
  }
  if (o.seed_only) legs_ = people::seed_only(legs_);
  people::LegPipeline2DConfig pipeline_config;
  pipeline_config.detector = legs_;
  pipeline_config.estimate_ego_motion = !o.still;
  pipeline_config.compact_occupancy_weight = o.compact_occupancy;
  pipeline_config.trace_segments = o.trace_segments;
  if (!config_text.empty())
    pipeline_config.joint =
        people::joint_tracker_config_from_yaml(config_text, config_path_, pipeline_config.joint);
  if (o.occupied_leg.size() == 2) {
    pipeline_config.occupied_leg_score_min = o.occupied_leg[0];
    pipeline_config.occupied_leg_evidence_min = o.occupied_leg[1];
  }
  pipeline_ = std::make_unique<people::LegPipeline2D>(pipeline_config);
}

FrameLegsPeople LegsRunner::process(const io::Frame& frame, const io::FrameSource& source,
                                    const std::optional<Pose>& T_fixed_sensor) {
  FrameLegsPeople out;
  clock_.check(frame);
  if (follow::is_planar_scan(frame.cloud)) {
    // A 2D scan is one ring: points in beam order. Persons are the pipeline's tracked people.
    if (!missing_config_.empty()) throw Error(missing_config_);
    ++scans_2d_;
    // Placed by a pose, a laser mounted upside down has its scan mirrored back (its heading is
    // its x axis either way).
    std::optional<Eigen::Isometry2d> pose;
    if (T_fixed_sensor) pose = isometry_2d(planar(*T_fixed_sensor));
    const bool over = T_fixed_sensor && people::upside_down(*T_fixed_sensor);
    auto det = pipeline_->process(frame.stamp_s, people::scan_points_2d(frame.cloud, over), pose);
    resampled_ += det.resampled;
    out.segments = std::move(det.segments);
    for (const auto& l : det.legs) out.legs.push_back(l.position_m);
    for (const auto& p : det.people) {
      out.persons.push_back(p.position_m);
      out.person_ids.push_back(p.track);
    }
    return out;
  }
  if (!sensor_) {
    sensor_ = source.sensor();
    if (!sensor_ && !options_.sensor.empty()) sensor_ = SensorModel::preset(options_.sensor);
    if (!sensor_)
      throw Error(options_.input + ": 3D frames of an unknown sensor: give --sensor (e.g. vlp16)");
  }
  follow_cfg_.legs = options_.config.empty() ? follow::FollowConfig::default_3d_legs() : legs_;
  PointCloud cloud = frame.cloud;
  follow::ensure_rings(cloud, *sensor_);  // KITTI and unorganised PCD have no ring field
  // A sweep tilted past the levelling's tolerance or turned over (a mount, a vehicle on a
  // slope) is levelled by its ground plane: the legs and persons are found and given in that
  // levelled frame (said once).
  const Pose T_level = levelling_pose(cloud, {}, options_.input, nullptr, &level_warned_);
  const auto per = follow::perceive(cloud, *sensor_, T_level, follow_cfg_);
  out.legs = per.legs_m;
  // Tracking in the sensor frame (the sensor is assumed still); confirmed tracks only.
  const auto upd = tracker_.update(frame.stamp_s, per.people_m);
  for (std::size_t i = 0; i < per.people_m.size(); ++i) {
    const auto id = upd.track_of_detection[i];
    const auto* t = id >= 0 ? tracker_.find(std::uint32_t(id)) : nullptr;
    if (!t || !t->confirmed) continue;
    out.persons.push_back(per.people_m[i]);
    out.person_ids.push_back(id);
  }
  return out;
}

const people::LegPipeline2DConfig& LegsRunner::config_2d() const {
  if (!missing_config_.empty()) throw Error(missing_config_);
  return pipeline_->config();
}

std::string LegsRunner::detector_summary() const {
  return "2D detector " + (config_path_.empty() ? std::string("defaults") : config_path_) +
         ", classifier " +
         (classifier_path_.empty() ? std::string("none (shape tests only)") : classifier_path_) +
         (resampled_ == 0
              ? std::string()
              : fmt::format("; {} of {} scans resampled to its {:.4f} deg step (a coarser laser "
                            "than it learned; their legs scored with a margin of {})",
                            resampled_, scans_2d_,
                            pipeline_->config().detector.classifier->scan_step_rad * 180.0 / M_PI,
                            pipeline_->config().resample_score_margin));
}

}  // namespace fieldlidar::app
