// fieldlidar legs INPUT: leg and person detection (seed 000, steps 2-5) on 2D laser scans (one
// ring) or 3D sweeps, with tracking, written as CSV; optional scoring against annotated legs.

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>

#include <fmt/core.h>

#include "commands.hpp"
#include "fieldlidar/core/error.hpp"
#include "fieldlidar/follow/pipeline.hpp"
#include "fieldlidar/io/file_util.hpp"
#include "fieldlidar/io/frame_source.hpp"
#include "fieldlidar/io/rosbag_reader.hpp"
#include "fieldlidar/people/leg_training.hpp"
#include "fieldlidar/people/tracker.hpp"

namespace fieldlidar::app {

namespace {

namespace fs = std::filesystem;

struct LegsOptions {
  std::string input;
  std::string topic;
  std::string out;
  std::string config;
  std::string truth_topic;
  std::string sensor;
  double match_radius_m = 0.15;
  bool seed_only = false;
  bool force = false;
};

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  if (!in) throw Error(p.string() + ": cannot be read");
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void run_legs(const LegsOptions& o) {
  const fs::path out(o.out);
  io::check_writable(out, o.force);
  people::LegDetectorConfig legs = people::default_2d_legs();
  if (!o.config.empty()) {
    legs = people::legs_config_from_yaml(read_text(o.config), o.config, legs);
    if (!legs.classifier_file.empty()) {
      // The learned classifier lives next to the config (legs-train writes both).
      fs::path model(legs.classifier_file);
      if (model.is_relative()) model = fs::path(o.config).parent_path() / model;
      legs.classifier = std::make_shared<const people::LegClassifier>(
          people::leg_classifier_from_yaml(read_text(model), model.string()));
    }
  }
  if (o.seed_only) legs = people::seed_only(legs);

  // Annotated legs per scan. The annotation bags record one PoseArray per scan, in step, with
  // stamps of their own: they are paired with the scans by order.
  std::vector<std::vector<Eigen::Vector2d>> truth;
  if (!o.truth_topic.empty())
    for (auto& s : io::read_pose_arrays(o.input, o.truth_topic)) {
      auto& v = truth.emplace_back();
      for (const auto& p : s.poses) v.emplace_back(p.translation().x(), p.translation().y());
    }

  io::SourceOptions so;
  so.topic = o.topic;
  auto source = io::FrameSource::open(o.input, so);
  people::TrackerConfig tc;
  tc.gate_max_m = 0.8;
  people::PersonTracker tracker(tc);
  follow::FollowConfig follow_cfg;
  std::optional<SensorModel> sensor;
  people::StaticBackground background;  // 2D: the sensor is assumed still

  std::string csv = "stamp,kind,x,y,track_id\n";
  std::size_t frames = 0, legs_total = 0, persons_total = 0, scored = 0;
  people::MatchCounts counts;
  char buf[160];
  while (auto frame = source->next()) {
    ++frames;
    std::vector<Eigen::Vector2d> leg_pos, person_pos;
    if (frame->cloud.ring_count() <= 1) {
      // A 2D scan is one ring: points in beam order.
      std::vector<Eigen::Vector2d> pts;
      pts.reserve(frame->cloud.size());
      for (const auto& p : frame->cloud.points)
        if (p.is_valid()) pts.emplace_back(p.x, p.y);
      const auto det = people::detect_legs_2d(pts, legs, &background);
      background.update(pts);
      for (const auto& l : det.legs) leg_pos.push_back(l.position_m);
      for (const auto& p : det.people) person_pos.push_back(p.position_m);
    } else {
      if (!sensor) {
        sensor = source->sensor();
        if (!sensor && !o.sensor.empty()) sensor = SensorModel::preset(o.sensor);
        if (!sensor)
          throw Error(o.input + ": 3D frames of an unknown sensor: give --sensor (e.g. vlp16)");
      }
      follow_cfg.legs = o.config.empty() ? follow::FollowConfig::default_3d_legs() : legs;
      const auto per = follow::perceive(frame->cloud, *sensor, Pose::Identity(), follow_cfg);
      leg_pos = per.legs_m;
      person_pos = per.people_m;
    }
    // Tracking in the sensor frame (the sensor is assumed still).
    const auto upd = tracker.update(frame->stamp_s, person_pos);
    for (const auto& l : leg_pos) {
      std::snprintf(buf, sizeof buf, "%.6f,leg,%.4f,%.4f,-1\n", frame->stamp_s, l.x(), l.y());
      csv += buf;
    }
    for (std::size_t i = 0; i < person_pos.size(); ++i) {
      const auto id = upd.track_of_detection[i];
      const auto* t = id >= 0 ? tracker.find(std::uint32_t(id)) : nullptr;
      std::snprintf(buf, sizeof buf, "%.6f,person,%.4f,%.4f,%lld\n", frame->stamp_s,
                    person_pos[i].x(), person_pos[i].y(),
                    static_cast<long long>(t && t->confirmed ? id : -1));
      csv += buf;
    }
    legs_total += leg_pos.size();
    persons_total += person_pos.size();
    if (frame->index < truth.size()) {
      counts += people::match_points(leg_pos, truth[frame->index], o.match_radius_m);
      ++scored;
    }
  }
  io::write_file_atomic(out, csv.data(), csv.size(), o.force);
  fmt::print("legs: {} scans, {} legs, {} person detections ({:.4f} per scan)\n", frames,
             legs_total, persons_total, frames ? double(persons_total) / double(frames) : 0.0);
  if (!o.truth_topic.empty())
    fmt::print(
        "legs vs {} ({} annotated scans, match {:.2f} m): recall {:.4f}, precision {:.4f} "
        "(tp {}, fp {}, fn {})\n",
        o.truth_topic, scored, o.match_radius_m, counts.recall(), counts.precision(),
        counts.true_positive, counts.false_positive, counts.false_negative);
  fmt::print("wrote {}\n", out.string());
}

}  // namespace

void add_legs_command(CLI::App& app) {
  auto o = std::make_shared<LegsOptions>();
  auto* cmd = app.add_subcommand(
      "legs", "Detect legs and people (and track people) in 2D scans or 3D sweeps");
  cmd->add_option("input", o->input, "Bag, capture or cloud files")->required();
  cmd->add_option("--topic", o->topic, "Bag topic of the scans");
  cmd->add_option("--out", o->out, "Detections CSV (stamp,kind,x,y,track_id)")->required();
  cmd->add_option("--config", o->config, "Leg detector YAML (from legs-train)");
  cmd->add_option("--truth", o->truth_topic,
                  "PoseArray topic of annotated legs: print recall and precision");
  cmd->add_option("--match-radius", o->match_radius_m, "Match distance for --truth (m)")
      ->capture_default_str();
  cmd->add_option("--sensor", o->sensor, "Sensor preset for 3D input without sensor metadata");
  cmd->add_flag("--seed-only", o->seed_only, "Only the seed's tests (no additions)");
  cmd->add_flag("--force", o->force, "Overwrite the output file");
  cmd->callback([o] { run_legs(*o); });
}

}  // namespace fieldlidar::app
