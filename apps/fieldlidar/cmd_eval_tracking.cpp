// fieldlidar eval-tracking INPUT: CLEAR MOT (MOTA, MOTP, misses, false positives, id switches)
// and person recall of tracked persons against annotated persons, as the leg_tracker benchmarks
// score 2D person trackers (0.75 m gate). INPUT is a ROS1 bag with leg_tracker/Person annotations
// (e.g. general_tracking_moving_1.bag) or a folder written by `fieldlidar simulate` (people.csv).
// The tracked persons come from the `legs` pipeline run on INPUT, or from a CSV `legs --out`
// wrote.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/file_util.hpp"
#include "fieldlidar/io/frame_source.hpp"
#include "fieldlidar/io/rosbag_reader.hpp"
#include "fieldlidar/io/trajectory_io.hpp"
#include "fieldlidar/people/clear_mot.hpp"
#include "fieldlidar/people/leg_training.hpp"
#include "support/legs_runner.hpp"
#include "support/warnings.hpp"

namespace fieldlidar::app {

namespace {

namespace fs = std::filesystem;
using people::IdentifiedPoint;
using PersonsPerFrame = std::vector<std::vector<IdentifiedPoint>>;

struct EvalTrackingOptions {
  std::string input;
  std::string topic;
  std::string truth_topic = "/ground_truth_people_tracks";
  std::string detections;
  std::vector<double> truth_wedge;  ///< bearing min, max (deg)
  double gate_m = 0.75;
  int truth_min_points = 0;  ///< simulated folders: persons hit by fewer returns are not scored
  bool paper_switches = false;
  bool json = false;
  LegsRunOptions legs;
};

/// The annotated persons per frame, in the sensor frame of each frame.
struct Truth {
  PersonsPerFrame persons;
  std::vector<double> stamps_s;  ///< per frame
  std::string frames_input;      ///< what FrameSource opens for the frames
  std::string topic;             ///< bag: the scan topic
  bool bag = false;
};

std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> out(1);
  for (char c : line) {
    if (c == ',')
      out.emplace_back();
    else
      out.back().push_back(c);
  }
  if (!out.back().empty() && out.back().back() == '\r') out.back().pop_back();
  return out;
}

double to_number(const std::string& s, const std::string& where) {
  try {
    std::size_t used = 0;
    const double v = std::stod(s, &used);
    if (used == s.size() && std::isfinite(v)) return v;
  } catch (...) {
  }
  throw Error(where + ": '" + s + "' is not a finite number");
}

/// Rows of a CSV with a header line as column name -> value callbacks.
template <class Row>
void read_csv(const fs::path& path, const std::vector<std::string>& columns, Row row) {
  const auto bytes = io::read_file_bytes(path);
  const std::string text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  std::vector<int> where(columns.size(), -1);
  std::size_t start = 0, line_no = 0;
  while (start < text.size()) {
    const std::size_t eol = std::min(text.find('\n', start), text.size());
    const auto cells = split_csv(text.substr(start, eol - start));
    start = eol + 1;
    ++line_no;
    if (line_no == 1) {
      for (std::size_t c = 0; c < columns.size(); ++c) {
        const auto it = std::find(cells.begin(), cells.end(), columns[c]);
        if (it == cells.end())
          throw Error(path.string() + ": no column '" + columns[c] + "' in the header");
        where[c] = int(it - cells.begin());
      }
      continue;
    }
    if (cells.size() == 1 && cells[0].empty()) continue;
    std::vector<std::string> picked;
    for (int w : where) {
      if (std::size_t(w) >= cells.size())
        throw Error(path.string() + ":" + std::to_string(line_no) + ": too few columns");
      picked.push_back(cells[std::size_t(w)]);
    }
    row(picked, path.string() + ":" + std::to_string(line_no));
  }
}

std::string only_scan_topic(const std::string& bag) {
  std::string found;
  for (const auto& t : io::bag_topics(bag))
    if (t.datatype == "sensor_msgs/LaserScan" || t.datatype == "sensor_msgs/PointCloud2") {
      if (!found.empty()) throw Error(bag + ": several scan topics, choose one with --topic");
      found = t.name;
    }
  if (found.empty()) throw Error(bag + ": no sensor_msgs/LaserScan or PointCloud2 topic");
  return found;
}

Truth bag_truth(const EvalTrackingOptions& o) {
  Truth t;
  t.bag = true;
  t.frames_input = o.input;
  t.topic = o.topic.empty() ? only_scan_topic(o.input) : o.topic;
  for (const auto& scan : io::read_person_annotations(o.input, t.topic, o.truth_topic)) {
    t.stamps_s.push_back(scan.scan_stamp_s);
    auto& v = t.persons.emplace_back();
    for (const auto& p : scan.people)
      v.push_back({p.id, Eigen::Vector2d(p.pose.translation().x(), p.pose.translation().y())});
  }
  return t;
}

/// A simulated folder: people.csv (world frame) moved into each frame's lidar frame at the sweep
/// start (poses.txt), frames read from pcd/ (they carry the rings).
Truth simulated_truth(const EvalTrackingOptions& o) {
  const fs::path dir(o.input);
  Truth t;
  t.frames_input = (dir / "pcd").string();
  const auto poses = io::read_kitti_poses(dir / "poses.txt", dir / "times.txt");
  t.persons.resize(poses.size());
  for (std::size_t i = 0; i < poses.size(); ++i) t.stamps_s.push_back(poses[i].stamp_s);
  read_csv(dir / "people.csv", {"frame", "id", "x_m", "y_m", "points"},
           [&](const std::vector<std::string>& c, const std::string& where) {
             if (to_number(c[4], where + " points") < o.truth_min_points) return;
             const double f = to_number(c[0], where + " frame");
             if (f < 0 || f >= double(poses.size()) || f != std::floor(f))
               throw Error(where + ": frame " + c[0] + " is not one of the " +
                           std::to_string(poses.size()) + " frames of poses.txt");
             const auto& T = poses[std::size_t(f)].pose;
             const Eigen::Vector3d world(to_number(c[2], where + " x_m"),
                                         to_number(c[3], where + " y_m"), T.translation().z());
             const Eigen::Vector3d local = T.inverse() * world;
             t.persons[std::size_t(f)].push_back(
                 {std::int64_t(to_number(c[1], where + " id")), local.head<2>()});
           });
  return t;
}

/// The sensor preset a simulated folder names in its scene.json ("" when it names none).
std::string simulated_sensor(const fs::path& dir) {
  const fs::path meta = dir / "scene.json";
  if (!fs::exists(meta)) return {};
  const auto bytes = io::read_file_bytes(meta);
  try {
    const auto j = nlohmann::json::parse(bytes.begin(), bytes.end());
    return j.value("sensor", std::string());
  } catch (const nlohmann::json::exception& e) {
    throw Error(meta.string() + ": not valid JSON (" + e.what() + ")");
  }
}

/// Person rows of a `legs --out` CSV, put in the frame whose stamp they carry.
PersonsPerFrame read_detections(const fs::path& csv, const std::vector<double>& stamps_s) {
  PersonsPerFrame out(stamps_s.size());
  std::vector<std::size_t> order(stamps_s.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return stamps_s[a] < stamps_s[b]; });
  read_csv(
      csv, {"stamp", "kind", "x", "y", "track_id"},
      [&](const std::vector<std::string>& c, const std::string& where) {
        if (c[1] != "person") return;
        const double stamp = to_number(c[0], where + " stamp");
        const auto it = std::lower_bound(order.begin(), order.end(), stamp,
                                         [&](std::size_t i, double s) { return stamps_s[i] < s; });
        std::size_t best = order.size();
        double best_dt = 1e-3;  // the CSV writes stamps to the microsecond
        for (auto j = it == order.begin() ? it : it - 1; j != order.end() && j <= it; ++j)
          if (std::abs(stamps_s[*j] - stamp) < best_dt)
            best = *j, best_dt = std::abs(stamps_s[*j] - stamp);
        if (best == order.size())
          throw Error(where + ": stamp " + c[0] + " is not the stamp of any scan of the input");
        out[best].push_back(
            {std::int64_t(to_number(c[4], where + " track_id")),
             Eigen::Vector2d(to_number(c[2], where + " x"), to_number(c[3], where + " y"))});
      });
  return out;
}

/// Runs the legs pipeline on the frames of `truth` and returns its tracked persons per frame.
PersonsPerFrame run_tracker(const EvalTrackingOptions& o, const Truth& truth) {
  LegsRunner runner(o.legs);
  io::SourceOptions so;
  so.topic = truth.topic;
  auto source = io::FrameSource::open(truth.frames_input, so);
  PersonsPerFrame out;
  while (auto frame = source->next()) {
    // A simulated folder's frame files carry no stamps: its times.txt is their clock.
    if (!truth.bag && frame->index < truth.stamps_s.size())
      frame->stamp_s = truth.stamps_s[frame->index];
    const auto found = runner.process(*frame, *source);
    auto& v = out.emplace_back();
    for (std::size_t i = 0; i < found.persons.size(); ++i)
      v.push_back({found.person_ids[i], found.persons[i]});
  }
  warn_source_losses(*source);
  if (out.size() != truth.persons.size())
    throw Error(o.input + ": " + std::to_string(out.size()) + " frames read but " +
                std::to_string(truth.persons.size()) + " frames of truth");
  return out;
}

std::vector<IdentifiedPoint> in_wedge(const std::vector<IdentifiedPoint>& v,
                                      const std::vector<double>& wedge) {
  if (wedge.size() != 2) return v;
  std::vector<IdentifiedPoint> out;
  const double inf = std::numeric_limits<double>::infinity();
  for (const auto& p : v)
    if (people::in_bearing_wedge(p.position_m, wedge[0], wedge[1], inf)) out.push_back(p);
  return out;
}

void run_eval_tracking(EvalTrackingOptions o) {
  if (o.truth_wedge.size() == 2 && !(o.truth_wedge[0] < o.truth_wedge[1]))
    throw Error(fmt::format("--truth-wedge: BEARING_MIN {} must be below BEARING_MAX {}",
                            o.truth_wedge[0], o.truth_wedge[1]));
  const bool folder = fs::is_directory(o.input);
  const Truth truth = folder ? simulated_truth(o) : bag_truth(o);
  if (folder && o.legs.sensor.empty()) o.legs.sensor = simulated_sensor(o.input);
  // The leg_tracker benchmark scores bearings -80..12 deg of its bags' laser frame.
  if (o.truth_wedge.empty() && truth.bag) o.truth_wedge = {-80.0, 12.0};
  o.legs.input = o.input;
  if (folder && !o.detections.empty())
    throw Error(
        "eval-tracking: --detections pairs tracked persons with frames by stamp, and the "
        "frame files of a simulated folder carry none: run without --detections");
  const PersonsPerFrame tracked =
      o.detections.empty() ? run_tracker(o, truth) : read_detections(o.detections, truth.stamps_s);

  people::ClearMotScorer scorer(
      {.gate_m = o.gate_m, .count_track_side_switches = !o.paper_switches});
  std::size_t annotated = 0, tracked_all = 0, scans_with_truth = 0;
  for (std::size_t f = 0; f < truth.persons.size(); ++f) {
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
                        {"mota", c.mota()},
                        {"recall", c.truth ? nlohmann::json(c.recall()) : nlohmann::json()},
                        {"motp_m", c.matches ? nlohmann::json(c.motp_m()) : nlohmann::json()}};
    j["truth_wedge_deg"] =
        o.truth_wedge.size() == 2 ? nlohmann::json(o.truth_wedge) : nlohmann::json();
    std::printf("%s\n", j.dump(2).c_str());
    return;
  }
  fmt::print(
      "eval-tracking: {} frames, {} annotated persons ({} scored, {}, in {} frames), {} "
      "tracked persons ({} scored), gate {:.2f} m\n",
      c.frames, annotated, c.truth, wedge, scans_with_truth, tracked_all, c.tracked, o.gate_m);
  fmt::print(
      "CLEAR MOT: MOTA {:.4f}, MOTP {} (matches {}, misses {}, false positives {}, id "
      "switches {})\n",
      c.mota(), c.matches ? fmt::format("{:.4f} m", c.motp_m()) : std::string("n/a"), c.matches,
      c.misses, c.false_positives, c.id_switches);
  fmt::print(
      "person recall {} ({} of {} annotated persons reported), {:.4f} false persons per "
      "frame\n",
      c.truth ? fmt::format("{:.4f}", c.recall()) : std::string("n/a"), c.matches, c.truth,
      c.false_positives_per_frame());
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
      ->check([](const std::string& v) {
        try {
          return std::isfinite(std::stod(v)) ? std::string() : "must be finite";
        } catch (...) {
          return std::string("must be a number");
        }
      });
  cmd->add_option("--truth-min-points", o->truth_min_points,
                  "Simulated folder: score only persons hit by at least this many returns "
                  "(people.csv `points`)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--gate", o->gate_m, "Match distance: strictly closer matches (m)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_flag("--paper-switches", o->paper_switches,
                "Count only the CLEAR MOT paper's id switches (an annotated person whose track "
                "changed), not also a track that moved to another person as the benchmark does");
  cmd->add_flag("--json", o->json, "Print machine-readable JSON");
  cmd->add_option("--config", o->legs.config, "Leg detector YAML (as for `fieldlidar legs`)");
  cmd->add_option("--sensor", o->legs.sensor, "Sensor preset for 3D input without metadata");
  cmd->add_flag("--still", o->legs.still, "2D: the sensor does not move");
  cmd->add_flag("--no-classifier", o->legs.no_classifier, "2D: shape tests only");
  cmd->add_flag("--seed-only", o->legs.seed_only, "Only the seed's tests");
  cmd->callback([o] { run_eval_tracking(*o); });
}

}  // namespace fieldlidar::app
