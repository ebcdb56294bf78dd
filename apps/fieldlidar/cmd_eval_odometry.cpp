// fieldlidar eval-odometry EST REF: the accuracy of an estimated trajectory against a reference, as
// the KITTI odometry devkit (drift over segments) and evo (RPE, ATE after alignment) report it.

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <fmt/core.h>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "fieldlidar/core/error.hpp"
#include "fieldlidar/core/trajectory_match.hpp"
#include "fieldlidar/core/trajectory_metrics.hpp"
#include "fieldlidar/io/file_util.hpp"
#include "fieldlidar/io/kitti_calib.hpp"
#include "fieldlidar/io/trajectory_io.hpp"
#include "support/option_checks.hpp"

namespace fieldlidar::app {

namespace {

struct EvalOdometryOptions {
  std::string estimate, reference, format = "auto", calib;
  std::vector<double> lengths_m;
  std::size_t step_frames = 10, delta_frames = 1, ref_stride = 1;
  double max_dt_s = 0.01;
  bool json = false;
};

/// "kitti" or "tum" from the first data line's number count (12 or 8) when `format` is "auto".
std::string format_of(const std::string& path, const std::string& format) {
  if (format == "kitti" || format == "tum") return format;
  if (format != "auto")
    throw Error("eval-odometry: --format '" + format + "' is not auto, kitti or tum");
  const auto bytes = io::read_file_bytes(path);
  const std::string text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  std::size_t start = 0;
  while (start < text.size()) {
    const std::size_t eol = std::min(text.find('\n', start), text.size());
    std::string line = text.substr(start, eol - start);
    start = eol + 1;
    line = line.substr(0, line.find('#'));
    int count = 0;
    bool in_token = false;
    for (char c : line) {
      const bool sep = c == ' ' || c == '\t' || c == '\r' || c == ',';
      if (!sep && !in_token) ++count;
      in_token = !sep;
    }
    if (count == 0) continue;
    if (count == 12) return "kitti";
    if (count == 8) return "tum";
    throw Error(path + ": first pose line has " + std::to_string(count) +
                " numbers: neither KITTI (12) nor TUM (8); give --format");
  }
  throw Error(path + ": no pose in the file");
}

Trajectory read_trajectory(const std::string& path, const std::string& format) {
  return format == "kitti" ? io::read_kitti_poses(path) : io::read_tum(path);
}

nlohmann::json stats_json(const ErrorStats& s) {
  return {{"count", s.count},   {"mean", s.mean}, {"rmse", s.rmse},
          {"median", s.median}, {"max", s.max},   {"std", s.std_dev}};
}

std::string lengths_text(const std::vector<double>& lengths) {
  std::vector<std::string> parts;
  for (double l : lengths) parts.push_back(fmt::format("{:g}", l));
  return fmt::format("{}", fmt::join(parts, ", "));
}

void print_text(const EvalOdometryOptions& o, const TrajectoryMetrics& m, const std::string& how) {
  fmt::print("poses:        {} ({})\n", m.pose_count, how);
  fmt::print("path length:  estimate {:.3f} m, reference {:.3f} m (ratio {:.4f})\n",
             m.estimate_path_m, m.reference_path_m, m.estimate_path_m / m.reference_path_m);
  const KittiDrift& d = m.drift;
  if (d.segment_count == 0) {
    fmt::print("KITTI drift:  n/a: no segment of {} m fits the {:.2f} m reference path\n",
               lengths_text(d.lengths_m), m.reference_path_m);
  } else {
    fmt::print("KITTI drift:  {:.3f} %, {:.4f} deg/m ({:.2f} deg/100 m) over {} segments\n",
               d.translation_pct, d.rotation_deg_per_m, 100.0 * d.rotation_deg_per_m,
               d.segment_count);
    fmt::print("  lengths:    {} m (a segment starts every {} frames)\n", lengths_text(d.lengths_m),
               o.step_frames);
    for (const auto& l : d.per_length)
      if (l.segment_count > 0)
        fmt::print("  {:>8g} m:  {:.3f} %, {:.4f} deg/m ({} segments)\n", l.length_m,
                   l.translation_pct, l.rotation_deg_per_m, l.segment_count);
  }
  const auto line = [](const char* name, const ErrorStats& s, double factor, const char* unit,
                       int digits) {
    fmt::print("  {:<13}rmse {:.{}f} {}, mean {:.{}f}, median {:.{}f}, max {:.{}f} ({} pairs)\n",
               name, factor * s.rmse, digits, unit, factor * s.mean, digits, factor * s.median,
               digits, factor * s.max, digits, s.count);
  };
  fmt::print("RPE ({} frame{}):\n", m.rpe.delta_frames, m.rpe.delta_frames == 1 ? "" : "s");
  line("translation", m.rpe.translation_m, 100.0, "cm", 2);
  line("rotation", m.rpe.rotation_deg, 1.0, "deg", 4);
  fmt::print("ATE:\n");
  line("SE(3)", m.ate_se3.translation_m, 1.0, "m", 4);
  line("Sim(3)", m.ate_sim3.translation_m, 1.0, "m", 4);
  fmt::print("  {:<13}{:.5f} (reference / estimate)\n", "Sim(3) scale", m.ate_sim3.alignment.scale);
  line("unaligned", m.ate_unaligned.translation_m, 1.0, "m", 4);
}

nlohmann::json metrics_json(const EvalOdometryOptions& o, const TrajectoryMetrics& m,
                            const std::string& how) {
  nlohmann::json j;
  j["estimate"] = o.estimate;
  j["reference"] = o.reference;
  j["matched"] = how;
  j["poses"] = m.pose_count;
  j["path_length_m"] = {{"estimate", m.estimate_path_m}, {"reference", m.reference_path_m}};
  nlohmann::json per_length = nlohmann::json::array();
  for (const auto& l : m.drift.per_length)
    per_length.push_back({{"length_m", l.length_m},
                          {"segments", l.segment_count},
                          {"translation_pct", l.translation_pct},
                          {"rotation_deg_per_m", l.rotation_deg_per_m}});
  j["kitti"] = {{"lengths_m", m.drift.lengths_m},
                {"step_frames", o.step_frames},
                {"segments", m.drift.segment_count},
                {"translation_pct", m.drift.translation_pct},
                {"rotation_deg_per_m", m.drift.rotation_deg_per_m},
                {"rotation_deg_per_100m", 100.0 * m.drift.rotation_deg_per_m},
                {"per_length", per_length}};
  j["rpe"] = {{"delta_frames", m.rpe.delta_frames},
              {"translation_m", stats_json(m.rpe.translation_m)},
              {"rotation_deg", stats_json(m.rpe.rotation_deg)}};
  j["ate"] = {{"se3", stats_json(m.ate_se3.translation_m)},
              {"sim3", stats_json(m.ate_sim3.translation_m)},
              {"sim3_scale", m.ate_sim3.alignment.scale},
              {"unaligned", stats_json(m.ate_unaligned.translation_m)}};
  return j;
}

void run(const EvalOdometryOptions& o) {
  for (double l : o.lengths_m)
    if (!(l > 0.0) || !std::isfinite(l))
      throw Error(fmt::format("eval-odometry: --lengths: {:g} is not a positive length (m)", l));
  const std::string est_format = format_of(o.estimate, o.format);
  const std::string ref_format = format_of(o.reference, o.format);
  const Trajectory estimate = read_trajectory(o.estimate, est_format);
  Trajectory reference = read_trajectory(o.reference, ref_format);
  if (!o.calib.empty()) reference = io::camera_to_lidar(reference, io::read_kitti_calib(o.calib));

  std::vector<Pose> est, ref;
  std::string how;
  if (est_format == "tum" && ref_format == "tum") {
    if (o.ref_stride != 1) throw Error("eval-odometry: --ref-stride is for files matched by row");
    const MatchedPoses matched = match_by_time(estimate, reference, o.max_dt_s);
    if (matched.indices.size() < 2)
      throw Error("eval-odometry: only " + std::to_string(matched.indices.size()) + " of the " +
                  std::to_string(estimate.size()) + " poses of " + o.estimate + " have a pose of " +
                  o.reference + " within --max-dt " + fmt::format("{:g}", o.max_dt_s) + " s");
    est = matched.a;
    ref = matched.b;
    how =
        fmt::format("matched by time: {} of {} estimate poses, {} reference poses, max dt {:.4f} s",
                    matched.indices.size(), estimate.size(), reference.size(), matched.max_dt_s);
  } else {
    for (const auto& sp : estimate) est.push_back(sp.pose);
    for (std::size_t i = 0; i < reference.size(); i += o.ref_stride)
      ref.push_back(reference[i].pose);
    if (est.size() != ref.size())
      throw Error("eval-odometry: " + o.estimate + " has " + std::to_string(est.size()) +
                  " poses but " + o.reference + " " + std::to_string(ref.size()) +
                  (o.ref_stride > 1 ? " (every " + std::to_string(o.ref_stride) + "th row)" : "") +
                  "; files without times are matched row by row (TUM files with times are "
                  "matched by time)");
    how = o.ref_stride > 1 ? fmt::format("matched by row, every {}th reference row", o.ref_stride)
                           : "matched by row";
  }
  // Without a pair the RPE would print rmse 0 over 0 pairs, which reads as a perfect estimate.
  if (o.delta_frames >= est.size())
    throw Error(fmt::format(
        "eval-odometry: --delta {}: no RPE pair in {} poses (the delta must be below the number "
        "of poses)",
        o.delta_frames, est.size()));
  TrajectoryMetricsConfig cfg;
  cfg.segment_lengths_m = o.lengths_m;
  cfg.segment_step_frames = o.step_frames;
  cfg.rpe_delta_frames = o.delta_frames;
  TrajectoryMetrics m;
  try {
    m = evaluate_trajectory(est, ref, cfg);
  } catch (const Error& e) {
    // The library names the pose ("estimate pose 3"); the user needs the files too.
    throw Error(fmt::format("eval-odometry: {} (estimate {}, reference {})", e.what(), o.estimate,
                            o.reference));
  }
  if (o.json) {
    std::printf("%s\n", metrics_json(o, m, how).dump(2).c_str());
    return;
  }
  print_text(o, m, how);
}

}  // namespace

void add_eval_odometry_command(CLI::App& app) {
  auto opts = std::make_shared<EvalOdometryOptions>();
  auto* cmd = app.add_subcommand(
      "eval-odometry",
      "Score an estimated trajectory against a reference: KITTI drift over segments, RPE per frame "
      "and ATE after SE(3) / Sim(3) alignment (rotations re-projected onto SO(3) first)");
  cmd->add_option("EST", opts->estimate, "Estimated trajectory (KITTI poses or TUM)")->required();
  cmd->add_option("REF", opts->reference, "Reference trajectory (KITTI poses or TUM)")->required();
  cmd->add_option("--format", opts->format,
                  "auto (12 numbers a line: KITTI, 8: TUM), kitti or tum; TUM pairs are matched "
                  "by time, anything else row by row")
      ->capture_default_str();
  cmd->add_option("--calib,--ref-calib", opts->calib,
                  "KITTI calib.txt: the reference is in the camera frame; take it to the LiDAR "
                  "frame (T_lidar = C^-1 T_cam C, C = R0_rect * Tr_velo_to_cam, or Tr)");
  cmd->add_option("--lengths", opts->lengths_m,
                  "Segment lengths (m) of the KITTI drift, e.g. 100,200,...,800; default: chosen "
                  "to fit the reference path")
      ->delimiter(',');
  cmd->add_option("--step", opts->step_frames, "Frames between segment starts (KITTI: 10)")
      ->capture_default_str()
      ->check(whole_in(1, 1000000));
  cmd->add_option("--delta", opts->delta_frames,
                  "Frame gap of the RPE; must be below the number of poses (an error otherwise: "
                  "no pair to score)")
      ->capture_default_str()
      ->check(whole_in(1, 1000000));
  cmd->add_option("--ref-stride", opts->ref_stride,
                  "Use every N-th reference row (an estimate of every N-th frame)")
      ->capture_default_str()
      ->check(whole_in(1, 1000000));
  cmd->add_option("--max-dt", opts->max_dt_s, "Largest time difference of a TUM pair (s)")
      ->capture_default_str()
      ->check(real_in(0, INFINITY));
  cmd->add_flag("--json", opts->json, "Print machine-readable JSON");
  cmd->callback([opts] { run(*opts); });
}

}  // namespace fieldlidar::app
