// fieldlidar eval-tracking INPUT: CLEAR MOT (MOTA, MOTP, misses, false positives, id switches)
// and person recall of tracked persons against annotated persons, as the leg_tracker benchmarks
// score 2D person trackers (0.75 m gate). INPUT is a ROS1 bag with leg_tracker/Person annotations
// (e.g. general_tracking_moving_1.bag) or a folder written by `fieldlidar simulate` (people.csv).
// The tracked persons come from the `legs` pipeline run on INPUT, or from a CSV `legs --out`
// wrote.

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/file_util.hpp"
#include "fieldlidar/io/frame_source.hpp"
#include "fieldlidar/people/clear_mot.hpp"
#include "fieldlidar/people/leg_training.hpp"
#include "fieldlidar/people/person_loss.hpp"
#include "support/legs_runner.hpp"
#include "support/losses_picture.hpp"
#include "support/option_checks.hpp"
#include "support/recorded_motion.hpp"
#include "support/tracking_truth.hpp"
#include "support/warnings.hpp"

namespace fieldlidar::app {

namespace {

namespace fs = std::filesystem;
using people::IdentifiedPoint;

struct EvalTrackingOptions {
  std::string input;
  std::string topic;
  std::string truth_topic = "/ground_truth_people_tracks";
  std::string detections;
  std::vector<double> truth_wedge;  ///< bearing min, max (deg)
  std::vector<std::size_t> scans;   ///< first, last scored frame (0-based, inclusive); all if empty
  double gate_m = 0.75;
  int truth_min_points = 0;  ///< simulated folders: persons hit by fewer returns are not scored
  bool paper_switches = false;
  bool json = false;
  bool losses = false;     ///< 2D: where each scored annotated person is lost
  std::string losses_csv;  ///< and one row per scored annotated person
  std::string losses_png;  ///< and a picture of them in the sensor frame
  bool force = false;      ///< replace an existing losses_csv or losses_png
  std::string odom;        ///< bag odometry topic or TUM pose file placing 2D scans
  LegsRunOptions legs;
};

/// One scored annotated person and the step of the legs pipeline where it was lost.
struct LossRow {
  std::size_t frame = 0;
  IdentifiedPoint truth;
  people::PersonLoss loss = people::PersonLoss::kNoSegment;
};

bool in_wedge(const Eigen::Vector2d& p, const std::vector<double>& wedge) {
  return wedge.size() != 2 ||
         people::in_bearing_wedge(p, wedge[0], wedge[1], std::numeric_limits<double>::infinity());
}

/// Runs the legs pipeline on the frames of `truth` and returns its tracked persons per frame;
/// with `losses`, also where each annotated person of frames `first`..`last` - 1 inside the
/// wedge was lost.
PersonsPerFrame run_tracker(const EvalTrackingOptions& o, const TrackingTruth& truth,
                            std::size_t first, std::size_t last, std::vector<LossRow>* losses) {
  auto legs_options = o.legs;
  legs_options.trace_segments = losses != nullptr;
  LegsRunner runner(legs_options);
  const people::PersonLossConfig loss_config{.gate_m = o.gate_m, .near_m = 2 * o.gate_m};
  std::optional<RecordedMotion> motion;
  if (!o.odom.empty()) motion = recorded_motion(truth.frames_input, o.odom, truth.topic);
  io::SourceOptions so;
  so.topic = truth.topic;
  auto source = io::FrameSource::open(truth.frames_input, so);
  PersonsPerFrame out;
  while (auto frame = source->next()) {
    const auto found = runner.process(
        *frame, *source,
        motion ? std::optional<Pose>(motion->sensor_at(frame->stamp_s)) : std::nullopt);
    auto& v = out.emplace_back();
    for (std::size_t i = 0; i < found.persons.size(); ++i)
      v.push_back({found.person_ids[i], found.persons[i]});
    const std::size_t f = out.size() - 1;
    if (!losses || f < first || f >= last || f >= truth.persons.size()) continue;
    if (!runner.scans_2d())
      throw Error(o.input + ": --losses traces the 2D legs pipeline; these frames are 3D");
    std::vector<people::PipelinePerson> reported;
    for (const auto& p : found.persons) reported.push_back({.position_m = p});
    for (const auto& t : truth.persons[f])
      if (in_wedge(t.position_m, o.truth_wedge))
        losses->push_back(
            {f, t, people::person_loss(t.position_m, found.segments, reported, loss_config)});
  }
  warn_source_losses(*source);
  if (motion) motion->warn_outside(o.odom);
  if (out.size() != truth.persons.size())
    throw Error(o.input + ": " + std::to_string(out.size()) + " frames read but " +
                std::to_string(truth.persons.size()) + " frames of truth");
  return out;
}

void write_losses_csv(const std::string& path, const std::vector<LossRow>& rows, bool force) {
  std::string text = "frame,truth_id,x_m,y_m,range_m,bearing_deg,loss\n";
  for (const auto& r : rows) {
    const auto& p = r.truth.position_m;
    text += fmt::format("{},{},{:.3f},{:.3f},{:.3f},{:.1f},{}\n", r.frame, r.truth.id, p.x(), p.y(),
                        p.norm(), std::atan2(p.y(), p.x()) * 180 / std::numbers::pi,
                        people::person_loss_name(r.loss));
  }
  io::write_file_atomic(path, text, force);
}

std::vector<IdentifiedPoint> in_wedge(const std::vector<IdentifiedPoint>& v,
                                      const std::vector<double>& wedge) {
  std::vector<IdentifiedPoint> out;
  for (const auto& p : v)
    if (in_wedge(p.position_m, wedge)) out.push_back(p);
  return out;
}

void run_eval_tracking(EvalTrackingOptions o) {
  if (o.truth_wedge.size() == 2 && !(o.truth_wedge[0] < o.truth_wedge[1]))
    throw Error(fmt::format("--truth-wedge: BEARING_MIN {} must be below BEARING_MAX {}",
                            o.truth_wedge[0], o.truth_wedge[1]));
  const bool folder = fs::is_directory(o.input);
  const TrackingTruth truth = folder ? simulated_person_truth(o.input, o.truth_min_points)
                                     : bag_person_truth(o.input, o.topic, o.truth_topic);
  if (folder && o.legs.sensor.empty()) o.legs.sensor = simulated_sensor(o.input);
  // The leg_tracker benchmark scores bearings -80..12 deg of its bags' laser frame.
  if (o.truth_wedge.empty() && truth.bag) o.truth_wedge = {-80.0, 12.0};
  o.legs.input = o.input;
  if (folder && !o.detections.empty())
    throw Error(
        "eval-tracking: --detections pairs tracked persons with frames by stamp, and the "
        "frame files of a simulated folder carry none: run without --detections");
  if (o.scans.size() == 2 && !(o.scans[0] <= o.scans[1] && o.scans[1] < truth.persons.size()))
    throw Error(fmt::format("--scans {}:{}: expected FIRST <= LAST < {} (the frames of {})",
                            o.scans[0], o.scans[1], truth.persons.size(), o.input));
  // The tracker runs on every frame (its tracks carry over); only the range is scored.
  const std::size_t first = o.scans.size() == 2 ? o.scans[0] : 0;
  const std::size_t last = o.scans.size() == 2 ? o.scans[1] + 1 : truth.persons.size();
  if (!o.losses_csv.empty() || !o.losses_png.empty()) o.losses = true;
  if (o.losses && !o.detections.empty())
    throw Error("eval-tracking: --losses traces the legs pipeline: run without --detections");
  // Before the run: a file the user has is not replaced without --force.
  if (!o.losses_csv.empty()) io::check_writable(o.losses_csv, o.force, {fs::path(o.input)});
  if (!o.losses_png.empty()) io::check_writable(o.losses_png, o.force, {fs::path(o.input)});
  std::vector<LossRow> losses;
  const PersonsPerFrame tracked =
      o.detections.empty() ? run_tracker(o, truth, first, last, o.losses ? &losses : nullptr)
                           : read_person_tracks_csv(o.detections, truth.stamps_s);
  people::PersonLossCounts loss_counts{};
  for (const auto& r : losses) ++loss_counts[std::size_t(r.loss)];
  if (!o.losses_csv.empty()) write_losses_csv(o.losses_csv, losses, o.force);
  if (!o.losses_png.empty()) {
    std::vector<PlacedLoss> placed;
    for (const auto& r : losses) placed.push_back({r.truth.position_m, r.loss});
    write_losses_picture(
        o.losses_png, placed, o.truth_wedge,
        fmt::format("eval-tracking {}: where the {} scored annotated persons are lost",
                    fs::path(o.input).filename().string(), losses.size()),
        o.force);
  }
  people::ClearMotScorer scorer(
      {.gate_m = o.gate_m, .count_track_side_switches = !o.paper_switches});
  std::size_t annotated = 0, tracked_all = 0, scans_with_truth = 0;
  for (std::size_t f = first; f < last; ++f) {
    annotated += truth.persons[f].size();
    tracked_all += tracked[f].size();
    const auto gt = in_wedge(truth.persons[f], o.truth_wedge);
    scans_with_truth += !gt.empty();
    scorer.add_frame(gt, in_wedge(tracked[f], o.truth_wedge));
  }
  const auto& c = scorer.totals();
  const std::string wedge =
      o.truth_wedge.size() == 2
          ? fmt::format("bearings {}..{} deg", o.truth_wedge[0], o.truth_wedge[1])
          : std::string("all bearings");
  if (o.json) {
    nlohmann::json j = {{"input", o.input},
                        {"tracks_from", o.detections.empty() ? "legs pipeline" : o.detections},
                        {"gate_m", o.gate_m},
                        {"frames", c.frames},
                        {"frames_with_truth", scans_with_truth},
                        {"annotated_persons", annotated},
                        {"truth_scored", c.truth},
                        {"tracked_persons", tracked_all},
                        {"tracked_scored", c.tracked},
                        {"matches", c.matches},
                        {"misses", c.misses},
                        {"false_positives", c.false_positives},
                        {"false_positives_per_frame", c.false_positives_per_frame()},
                        {"id_switches", c.id_switches},
                        {"mota", c.truth ? nlohmann::json(c.mota()) : nlohmann::json()},
                        {"recall", c.truth ? nlohmann::json(c.recall()) : nlohmann::json()},
                        {"motp_m", c.matches ? nlohmann::json(c.motp_m()) : nlohmann::json()}};
    j["scans"] = o.scans.size() == 2 ? nlohmann::json(o.scans) : nlohmann::json();
    j["truth_wedge_deg"] =
        o.truth_wedge.size() == 2 ? nlohmann::json(o.truth_wedge) : nlohmann::json();
    if (o.losses) {
      nlohmann::json l = nlohmann::json::object();
      for (std::size_t k = 0; k < people::kPersonLosses; ++k)
        l[std::string(people::person_loss_name(people::PersonLoss(k)))] = loss_counts[k];
      j["losses"] = l;
    }
    std::printf("%s\n", j.dump(2).c_str());
    return;
  }
  fmt::print(
      "eval-tracking: {} frames, {} annotated persons ({} scored, {}, in {} frames), {} "
      "tracked persons ({} scored), gate {:.2f} m\n",
      c.frames, annotated, c.truth, wedge, scans_with_truth, tracked_all, c.tracked, o.gate_m);
  fmt::print(
      "CLEAR MOT: MOTA {}, MOTP {} (matches {}, misses {}, false positives {}, id "
      "switches {})\n",
      c.truth ? fmt::format("{:.4f}", c.mota()) : std::string("n/a"),
      c.matches ? fmt::format("{:.4f} m", c.motp_m()) : std::string("n/a"), c.matches, c.misses,
      c.false_positives, c.id_switches);
  fmt::print(
      "person recall {} ({} of {} annotated persons reported), {:.4f} false persons per "
      "frame\n",
      c.truth ? fmt::format("{:.4f}", c.recall()) : std::string("n/a"), c.matches, c.truth,
      c.false_positives_per_frame());
  if (o.losses) {
    fmt::print("where the {} scored annotated persons are lost (furthest step reached):\n",
               losses.size());
    for (std::size_t k = 0; k < people::kPersonLosses; ++k)
      fmt::print("  {:<22} {}\n", people::person_loss_name(people::PersonLoss(k)), loss_counts[k]);
  }
}

}  // namespace

void add_eval_tracking_command(CLI::App& app) {
  auto o = std::make_shared<EvalTrackingOptions>();
  auto* cmd = app.add_subcommand(
      "eval-tracking",
      "CLEAR MOT (MOTA, MOTP, misses, false positives, id switches) and person recall of tracked "
      "persons against annotated ones");
  cmd->add_option("input", o->input,
                  "ROS1 bag with leg_tracker/Person annotations, or a folder written by "
                  "`fieldlidar simulate` (people.csv)")
      ->required();
  cmd->add_option("--topic", o->topic, "Bag topic of the scans (default: the only scan topic)");
  cmd->add_option("--odom", o->odom,
                  "2D: place the scans by the recording's odometry instead of matching them: a "
                  "nav_msgs/Odometry topic of the bag (the laser's mount from its /tf), or a TUM "
                  "pose file of the sensor (e.g. a simulator folder's poses_tum.txt)");
  cmd->add_option("--truth", o->truth_topic, "Bag topic of the leg_tracker/Person annotations")
      ->capture_default_str();
  cmd->add_option("--detections", o->detections,
                  "Tracked persons from a `fieldlidar legs --out` CSV instead of running the "
                  "legs pipeline on INPUT");
  cmd->add_option("--truth-wedge", o->truth_wedge,
                  "Score only annotated and tracked persons at bearings BEARING_MIN..BEARING_MAX "
                  "(deg, 0 = x forward, counter-clockwise positive); default for bags: -80 12, "
                  "the leg_tracker benchmark's")
      ->expected(2)
      ->check(real_finite());
  cmd->add_option("--scans", o->scans,
                  "Score only frames FIRST..LAST (0-based, inclusive; e.g. 0:436); the tracker "
                  "still runs on every frame")
      ->delimiter(':')
      ->expected(2);
  cmd->add_option("--truth-min-points", o->truth_min_points,
                  "Simulated folder: score only persons hit by at least this many returns "
                  "(people.csv `points`)")
      ->capture_default_str()
      ->check(whole_in(0, std::numeric_limits<int>::max()));
  cmd->add_option("--gate", o->gate_m, "Match distance: strictly closer matches (m)")
      ->capture_default_str()
      ->check(real_above(0));
  cmd->add_flag("--paper-switches", o->paper_switches,
                "Count only the CLEAR MOT paper's id switches (an annotated person whose track "
                "changed), not also a track that moved to another person as the benchmark does");
  cmd->add_flag("--json", o->json, "Print machine-readable JSON");
  cmd->add_flag("--losses", o->losses,
                "2D: count where each scored annotated person is lost in the legs pipeline (the "
                "furthest step its scan segments reached: no segment, not a candidate, "
                "background, not a leg, occupied space, no person track, not reported) or "
                "reported");
  cmd->add_option("--losses-csv", o->losses_csv,
                  "2D: also write one row per scored annotated person with its loss (implies "
                  "--losses); an existing file is replaced only with --force");
  cmd->add_option("--losses-png", o->losses_png,
                  "2D: also draw each scored annotated person in the sensor frame, coloured by its "
                  "loss (implies --losses); an existing file is replaced only with --force");
  cmd->add_flag("--force", o->force, "Replace an existing --losses-csv or --losses-png file");
  cmd->add_option("--config", o->legs.config,
                  "Leg detector YAML with its optional `tracker:` map (as for `fieldlidar legs`)");
  cmd->add_option("--sensor", o->legs.sensor, "Sensor preset for 3D input without metadata");
  cmd->add_flag("--still", o->legs.still, "2D: the sensor does not move");
  cmd->add_flag("--no-classifier", o->legs.no_classifier, "2D: shape tests only");
  cmd->add_option(
         "--compact-occupancy", o->legs.compact_occupancy,
         "2D: weight (0..1) of a leg-sized segment's returns in the occupancy grid where no person "
         "track lives; 0 keeps people who stand while the robot drives past trackable, and "
         "leg-shaped furniture too")
      ->capture_default_str()
      ->check(real_in(0, 1));
  cmd->add_flag("--seed-only", o->legs.seed_only, "Only the seed's tests");
  cmd->callback([o] { run_eval_tracking(*o); });
}

}  // namespace fieldlidar::app
