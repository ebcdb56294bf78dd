// fieldlidar legs INPUT: leg and person detection (seed 000, steps 2-5) on 2D laser scans (one
// ring) or 3D sweeps, with tracking, written as CSV; optional scoring against annotated legs.
// 2D scans go through people::LegPipeline2D (learned classifier, leg tracks, ego-motion by scan
// matching, persons once they walk); 3D sweeps through the follow pipeline's perception.

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <set>
#include <string>

#include <fmt/core.h>

#include "commands.hpp"
#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/file_util.hpp"
#include "fieldlidar/io/frame_source.hpp"
#include "fieldlidar/io/rosbag_reader.hpp"
#include "fieldlidar/people/leg_training.hpp"
#include "support/frame_clock.hpp"
#include "support/legs_runner.hpp"
#include "support/option_checks.hpp"
#include "support/recorded_motion.hpp"
#include "support/sensor_choice.hpp"
#include "support/warnings.hpp"

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
  std::vector<double> truth_wedge;  ///< bearing min, max (deg), range max (m)
  bool seed_only = false;
  bool still = false;
  double compact_occupancy = 1.0;
  std::vector<double> occupied_leg;
  bool no_classifier = false;
  bool force = false;
  double rate_hz = 0;  ///< > 0: frames stamped at this rate from the first one's stamp
  std::string odom;    ///< bag odometry topic or TUM pose file placing 2D scans
};

void run_legs(const LegsOptions& o) {
  if (o.truth_wedge.size() == 3) {
    require(o.truth_wedge[0] < o.truth_wedge[1], "--truth-wedge",
            fmt::format("BEARING_MIN {} must be below BEARING_MAX {}", o.truth_wedge[0],
                        o.truth_wedge[1]));
    require(o.truth_wedge[2] > 0, "--truth-wedge",
            fmt::format("RANGE_MAX {} must be > 0", o.truth_wedge[2]));
  }
  const fs::path out(o.out);
  io::check_writable(out, o.force, {o.input});
  LegsRunner runner({.input = o.input,
                     .config = o.config,
                     .sensor = o.sensor,
                     .seed_only = o.seed_only,
                     .still = o.still,
                     .no_classifier = o.no_classifier,
                     .compact_occupancy = o.compact_occupancy,
                     .occupied_leg = o.occupied_leg});

  // Annotated legs per scan. The annotation bags record one PoseArray per scan, in step, with
  // stamps of their own: they are paired with the scans by order.
  std::vector<std::vector<Eigen::Vector2d>> truth;
  if (!o.truth_topic.empty())
    for (auto& s : io::read_pose_arrays(o.input, o.truth_topic)) {
      auto& v = truth.emplace_back();
      for (const auto& p : s.poses) v.emplace_back(p.translation().x(), p.translation().y());
    }

  std::optional<RecordedMotion> motion;
  if (!o.odom.empty()) motion = recorded_motion(o.input, o.odom, o.topic);
  io::SourceOptions so;
  so.topic = o.topic;
  auto source = io::FrameSource::open(o.input, so);
  std::string csv = "stamp,kind,x,y,track_id\n";
  std::size_t frames = 0, points = 0, legs_total = 0, persons_total = 0, scored = 0;
  std::set<long long> person_ids;  // distinct tracked persons
  people::MatchCounts counts;
  char buf[160];
  std::optional<double> first_stamp_s;
  while (auto frame = source->next()) {
    ++frames;
    points += frame->cloud.size();
    stamp_at_rate(*frame, o.rate_hz, first_stamp_s);
    const auto found = runner.process(
        *frame, *source,
        motion ? std::optional<Pose>(motion->sensor_at(frame->stamp_s)) : std::nullopt);
    const auto& leg_pos = found.legs;
    const auto& person_pos = found.persons;
    const auto& person_id = found.person_ids;
    for (const auto& l : leg_pos) {
      std::snprintf(buf, sizeof buf, "%.6f,leg,%.4f,%.4f,-1\n", frame->stamp_s, l.x(), l.y());
      csv += buf;
    }
    for (std::size_t i = 0; i < person_pos.size(); ++i) {
      std::snprintf(buf, sizeof buf, "%.6f,person,%.4f,%.4f,%lld\n", frame->stamp_s,
                    person_pos[i].x(), person_pos[i].y(), (long long)person_id[i]);
      csv += buf;
    }
    legs_total += leg_pos.size();
    persons_total += person_pos.size();
    person_ids.insert(person_id.begin(), person_id.end());
    if (frame->index < truth.size()) {
      std::vector<char> matched;
      auto m = people::match_points(leg_pos, truth[frame->index], o.match_radius_m, &matched);
      if (o.truth_wedge.size() == 3)
        for (std::size_t i = 0; i < leg_pos.size(); ++i) {
          const bool inside = people::in_bearing_wedge(leg_pos[i], o.truth_wedge[0],
                                                       o.truth_wedge[1], o.truth_wedge[2]);
          if (!matched[i] && !inside) --m.false_positive;  // not annotated there: not scored
        }
      counts += m;
      ++scored;
    }
  }
  warn_source_losses(*source);
  if (motion) motion->warn_outside(o.odom);
  if (points == 0)
    throw Error(o.input + (frames ? ": holds no points" : ": holds no scans") +
                ": no legs to look for");
  io::write_file_atomic(out, csv, o.force);
  fmt::print(
      "legs: {} scans, {} legs, {} tracked persons ({} person detections, {:.4f} per scan)\n",
      frames, legs_total, person_ids.size(), persons_total,
      frames ? double(persons_total) / double(frames) : 0.0);
  if (!o.truth_topic.empty())
    fmt::print(
        "legs vs {} ({} annotated scans, match {:.2f} m{}): recall {:.4f}, precision {:.4f} "
        "(tp {}, fp {}, fn {})\n",
        o.truth_topic, scored, o.match_radius_m,
        o.truth_wedge.size() == 3
            ? fmt::format(", precision inside bearing {}..{} deg, range <= {} m", o.truth_wedge[0],
                          o.truth_wedge[1], o.truth_wedge[2])
            : std::string(),
        counts.recall(), counts.precision(), counts.true_positive, counts.false_positive,
        counts.false_negative);
  if (runner.scans_2d()) fmt::print("legs: {}\n", runner.detector_summary());
  fmt::print("wrote {}\n", out.string());
}

}  // namespace

void add_legs_command(CLI::App& app) {
  auto o = std::make_shared<LegsOptions>();
  auto* cmd = app.add_subcommand(
      "legs", "Detect legs and people (and track people) in 2D scans or 3D sweeps");
  cmd->add_option("input", o->input, "Bag, capture or cloud files")->required();
  cmd->add_option("--topic", o->topic, "Bag topic of the scans");
  cmd->add_option("--odom", o->odom,
                  "2D: place the scans by the recording's odometry instead of matching them: a "
                  "nav_msgs/Odometry topic of the bag (the laser's mount from its /tf), or a TUM "
                  "pose file of the sensor (e.g. a simulator folder's poses_tum.txt)");
  cmd->add_option("--rate", o->rate_hz,
                  "Stamp the frames at this rate (Hz) from the first one's stamp, for frames "
                  "without a clock (a folder of frames with no times.txt in or beside it)")
      ->check(real_above(0, 1e4));
  cmd->add_option("--out", o->out, "Detections CSV (stamp,kind,x,y,track_id)")->required();
  cmd->add_option("--config", o->config,
                  "Leg detector YAML (from legs-train; default for 2D scans: the shipped "
                  "config/legs_2d.yaml with its learned classifier); its optional `tracker:` map "
                  "sets the 2D person tracker (keys and units: that file)");
  cmd->add_option("--truth", o->truth_topic,
                  "PoseArray topic of annotated legs: print recall and precision");
  cmd->add_option("--match-radius", o->match_radius_m, "Match distance for --truth (m)")
      ->capture_default_str()
      ->check(real_above(0, 5));
  cmd->add_option(
         "--truth-wedge", o->truth_wedge,
         "The region where --truth annotates every leg: BEARING_MIN BEARING_MAX (deg) "
         "RANGE_MAX (m); unmatched legs outside it are not scored (legs_2d bags: -15 15 5)")
      ->expected(3)
      ->check(real_in(-180, 180));
  cmd->add_option("--sensor", o->sensor, "Sensor preset for 3D input without sensor metadata")
      ->check(sensor_preset());
  cmd->add_flag("--seed-only", o->seed_only, "Only the seed's tests (no additions, no classifier)");
  cmd->add_flag("--still", o->still,
                "2D: the sensor does not move (no ego-motion estimation by scan matching)");
  cmd->add_flag("--no-classifier", o->no_classifier,
                "2D: no learned leg classifier, shape tests only (without this flag a missing "
                "shipped classifier is an error)");
  cmd->add_option(
         "--compact-occupancy", o->compact_occupancy,
         "2D: weight (0..1) of a leg-sized segment's returns in the occupancy grid where no person "
         "track lives; 0 keeps people who stand while the robot drives past trackable, and "
         "leg-shaped furniture too")
      ->capture_default_str()
      ->check(real_in(0, 1));
  cmd->add_option("--occupied-leg", o->occupied_leg,
                  "2D: SCORE EVIDENCE: a leg on occupied space (returns there scan after scan) is "
                  "reported only if its classifier score passes the threshold by SCORE or its "
                  "track's evidence reaches EVIDENCE (default: the margins the classifier file "
                  "carries, 3 7 in the shipped one, none in one from legs-train, whose scores "
                  "are on another scale; -1e9 -1e9: no such rule)")
      ->expected(2)
      ->check(real_finite());
  cmd->add_flag("--force", o->force, "Overwrite the output file");
  cmd->callback([o] { run_legs(*o); });
}

}  // namespace fieldlidar::app
