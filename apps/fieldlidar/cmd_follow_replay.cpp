// fieldlidar follow --replay BAG: the follow pipeline on a real recording. Perception, tracking,
// target choice, safety rule and controller run as on the mower; the robot's motion is the
// recording's (its odometry topic, or standing still), so the wheel commands are logged only.

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/follow/replay.hpp"
#include "fieldlidar/io/file_util.hpp"
#include "fieldlidar/io/frame_source.hpp"
#include "fieldlidar/loops/closed_loop.hpp"
#include "follow_job.hpp"
#include "support/follow_replay_picture.hpp"
#include "support/frame_clock.hpp"
#include "support/legs_runner.hpp"
#include "support/option_checks.hpp"
#include "support/progress_line.hpp"
#include "support/recorded_motion.hpp"
#include "support/sweep_levelling.hpp"
#include "support/warnings.hpp"

namespace fieldlidar::app {

namespace {

namespace fs = std::filesystem;

loops::LogRow log_row(const follow::ReplayFrame& f) {
  loops::LogRow r;
  r.t_s = f.stamp_s;
  r.mower_x = r.mower_est_x = f.mower.x_m;
  r.mower_y = r.mower_est_y = f.mower.y_m;
  r.mower_yaw = r.mower_est_yaw = f.mower.yaw_rad;
  if (f.output.target_world_m) {
    r.est_x = f.output.target_world_m->x();
    r.est_y = f.output.target_world_m->y();
  }
  r.true_x = r.true_y = r.true_distance_m = NAN;  // a recording has no truth
  r.distance_m = f.output.control.distance_m >= 0 ? f.output.control.distance_m : NAN;
  r.wheel_left = f.output.control.command.left_m_s;
  r.wheel_right = f.output.control.command.right_m_s;
  r.state = f.output.control.state;
  r.target_id = f.output.target_id ? std::int64_t(*f.output.target_id) : -1;
  r.people_detected = f.people_detected;
  r.perception_ms = f.perception_ms;
  return r;
}

}  // namespace

void run_follow_replay(const FollowOptions& o) {
  follow::ReplayConfig cfg;
  if (o.target_id >= 0) cfg.follow.target_id = std::uint32_t(o.target_id);
  if (o.safe_distance_m > 0) cfg.follow.safety.safe_distance_m = o.safe_distance_m;
  if (o.max_distance_m > 0) cfg.follow.safety.max_distance_m = o.max_distance_m;
  require(cfg.follow.safety.safe_distance_m < cfg.follow.safety.max_distance_m, "--safe-distance",
          fmt::format("{} m must be below --max-distance {} m", cfg.follow.safety.safe_distance_m,
                      cfg.follow.safety.max_distance_m));
  const fs::path dir(o.out), log = dir / "follow_log.csv", summary = dir / "summary.json",
                             png = dir / "follow.png";
  if (fs::exists(dir) && !fs::is_directory(dir))
    throw Error("--out " + o.out + ": exists and is not a folder");
  if (fs::is_directory(dir))
    for (const auto& p : {log, summary, png}) io::check_writable(p, o.force);

  const fs::path input(o.replay);  // a bag, or frames (a simulator folder: its pcd/ sweeps)
  std::optional<RecordedMotion> motion;
  if (!o.odom_topic.empty()) {
    motion = recorded_motion(input, o.odom_topic, o.topic);
    cfg.T_base_sensor = motion->T_base_sensor;
  }
  io::SourceOptions so;
  so.topic = o.topic;
  auto source = io::FrameSource::open(input, so);
  std::string mount_from = motion ? motion->mount_from : "none (the sensor is the base)";
  if (!o.mount.empty()) {
    const auto& m = o.mount;
    require(std::all_of(m.begin(), m.end(), [](double v) { return std::isfinite(v); }) &&
                std::abs(m[0]) <= 100 && std::abs(m[1]) <= 100 && std::abs(m[2]) <= 100,
            "--mount", "X,Y,Z must be finite metres within 100 m of the base, angles finite");
    constexpr double kDeg = M_PI / 180.0;
    cfg.T_base_sensor = make_pose(m[0], m[1], m[2], m[3] * kDeg, m[4] * kDeg, m[5] * kDeg);
    mount_from = "--mount" + (motion ? " (in place of " + mount_from + ")" : std::string());
  }
  LegsRunOptions lo;
  lo.input = o.replay;
  lo.config = o.legs_config;
  LegsRunner legs(lo);
  std::optional<follow::FollowReplay> replay;
  std::vector<loops::LogRow> rows;
  std::string topic;
  std::optional<double> max_time_end;
  ProgressLine progress;
  FrameClock clock(
      o.replay,
      "a folder of frames takes its clock from a KITTI-style times.txt in or beside it "
      "(`--rate HZ` stamps frames without one)");
  std::optional<double> first_stamp_s;
  nlohmann::json levelling;
  while (auto frame = source->next()) {
    if (!replay) {
      const bool planar = follow::is_planar_scan(frame->cloud);
      if (planar) cfg.legs_2d = legs.config_2d();
      // Without the recording's mount (--odom's /tf), a 3D sensor mounted tilted or upside down
      // is levelled by the ground plane below its first sweep: the robot stands still, so the
      // mount is one rotation for the whole replay.
      if (!motion && !planar && o.mount.empty()) {
        cfg.T_base_sensor = levelling_pose(frame->cloud, {}, o.replay, &levelling);
        if (levelling["levelled"].get<bool>())
          mount_from =
              fmt::format("levelled by the ground below the first sweep (tilted {:.1f} deg{})",
                          levelling["tilt_deg"].get<double>(),
                          levelling["upside_down"].get<bool>() ? ", upside down" : "");
      }
      auto sensor = source->sensor();
      if (!sensor) sensor = SensorModel::preset(o.sensor);
      if (!sensor) throw Error("--sensor '" + o.sensor + "': unknown sensor preset");
      replay.emplace(*sensor, cfg);
      topic = frame->topic;
      if (o.max_time_s > 0) max_time_end = frame->stamp_s + o.max_time_s;
    }
    stamp_at_rate(*frame, o.rate_hz, first_stamp_s);
    clock.check(*frame);
    if (max_time_end && frame->stamp_s > *max_time_end) break;
    std::optional<Pose> pose;
    if (motion) pose = motion->base_at(frame->stamp_s);
    rows.push_back(log_row(replay->step(frame->cloud, frame->stamp_s, pose)));
    progress.show("frame {} ({:.0f} %)   ", frame->index, 100 * source->progress());
  }
  progress.end();
  if (!replay) throw Error(o.replay + ": no frame on the scan topic");
  for (const auto& w : source->warnings()) warn(w);
  if (motion) motion->warn_outside(o.odom_topic);

  const auto& s = replay->summary();
  auto state_frames = [&](follow::FollowState st) { return s.frames_by_state[std::size_t(st)]; };
  nlohmann::json j;
  j["replay"] = o.replay;
  j["topic"] = topic;
  j["odom_topic"] = o.odom_topic;
  j["motion"] = motion ? "the recording's odometry (" + o.odom_topic + ")" : "standing still";
  j["detector"] = legs.detector_summary();
  j["sensor_mount"] = {{"from", mount_from},
                       {"x_m", cfg.T_base_sensor.translation().x()},
                       {"y_m", cfg.T_base_sensor.translation().y()},
                       {"yaw_deg", yaw_of(cfg.T_base_sensor) * 180 / M_PI}};
  if (!levelling.is_null()) j["sensor_mount"]["levelling"] = levelling;
  j["frames"] = s.frames;
  j["duration_s"] = s.duration_s;
  j["frame"] = motion ? "odometry frame of the recording, x-y in metres"
                      : "sensor frame (the robot stands still), x-y in metres";
  j["metrics"] = {{"target_id", s.first_target_id ? std::int64_t(*s.first_target_id) : -1},
                  {"frames_before_target_chosen", s.frames - s.frames_with_target_chosen},
                  {"frames_target_held", s.frames_target_held},
                  {"target_held_fraction", s.target_held_fraction()},
                  {"target_held_fraction_of_all_frames",
                   s.frames ? double(s.frames_target_held) / double(s.frames) : 0.0},
                  {"recording_gaps", s.recording_gaps},
                  {"frames_lost_after_gaps", s.frames_lost_after_gaps},
                  {"target_held_fraction_between_gaps", s.target_held_fraction_between_gaps()},
                  {"target_switches", s.target_switches},
                  {"distinct_target_ids", s.distinct_target_ids},
                  {"frames_following", s.frames_following},
                  {"stops", s.stops},
                  {"frames_stopped",
                   {{"idle_no_target", state_frames(follow::FollowState::kIdle)},
                    {"too_close", state_frames(follow::FollowState::kTooClose)},
                    {"too_far", state_frames(follow::FollowState::kTooFar)},
                    {"lost", state_frames(follow::FollowState::kLost)}}},
                  {"path_length_m", s.path_length_m},
                  {"mean_perception_ms", s.mean_perception_ms},
                  {"max_perception_ms", s.max_perception_ms}};
  j["safety"] = {{"L_s_m", cfg.follow.safety.safe_distance_m},
                 {"L_m_m", cfg.follow.safety.max_distance_m}};
  fs::create_directories(dir);
  io::write_file_atomic(log, loops::log_csv(rows), o.force);
  io::write_file_atomic(summary, j.dump(2) + "\n", o.force);
  write_follow_replay_picture(
      png, rows, cfg.gap_s,
      fmt::format("follow --replay {}: target held in {:.1f} % of the scans since chosen",
                  fs::path(o.replay).filename().string(), 100 * s.target_held_fraction()),
      o.force);
  fmt::print(
      "follow replay: {} frames ({:.1f} s), {}; target id {} held in {:.1f} % of the frames since "
      "chosen ({} switches){}; following {} frames; stopped: {} idle, {} too close, {} too far, "
      "{} lost ({} stops); perception {:.2f} ms per frame\nwrote {}\n",
      s.frames, s.duration_s, motion ? "recorded odometry" : "standing still",
      s.first_target_id ? std::int64_t(*s.first_target_id) : -1, 100 * s.target_held_fraction(),
      s.target_switches,
      s.recording_gaps
          ? fmt::format(", {:.1f} % without the {} frames lost after the "
                        "recording's {} break{} of over {:.1f} s",
                        100 * s.target_held_fraction_between_gaps(), s.frames_lost_after_gaps,
                        s.recording_gaps, s.recording_gaps > 1 ? "s" : "", cfg.gap_s)
          : std::string(),
      s.frames_following, state_frames(follow::FollowState::kIdle),
      state_frames(follow::FollowState::kTooClose), state_frames(follow::FollowState::kTooFar),
      state_frames(follow::FollowState::kLost), s.stops, s.mean_perception_ms, dir.string());
}

}  // namespace fieldlidar::app
