#include "fieldlidar/loops/closed_loop.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>

#include "fieldlidar/sim/lidar_simulator.hpp"

namespace fieldlidar::loops {

using follow::compare_closed;
using follow::FollowPipeline;
using follow::FollowState;
using follow::Pose2;
using follow::predict_pose;
using follow::WheelCommand;

std::string to_string(Scenario s) {
  switch (s) {
    case Scenario::kDefault:
      return "default";
    case Scenario::kCrossing:
      return "crossing";
    case Scenario::kStop:
      return "stop";
    case Scenario::kFast:
      return "fast";
    case Scenario::kOccluded:
      return "occluded";
  }
  return "default";
}

std::optional<Scenario> scenario_from_string(const std::string& n) {
  for (auto s : {Scenario::kDefault, Scenario::kCrossing, Scenario::kStop, Scenario::kFast,
                 Scenario::kOccluded})
    if (to_string(s) == n) return s;
  return std::nullopt;
}

sim::LawnConfig lawn_config(Scenario s) {
  sim::LawnConfig c;
  c.second_person_crossing = s == Scenario::kCrossing;
  c.operator_stops = s == Scenario::kStop;
  c.operator_too_fast = s == Scenario::kFast;
  c.operator_behind_shed = s == Scenario::kOccluded;
  return c;
}

namespace {

Pose lidar_pose(const sim::Scene& scene, const Pose2& m) {
  const double z = scene.ground_height_at(m.xy()) + scene.sensor_height_m();
  return make_pose(m.x_m, m.y_m, z, 0, 0, m.yaw_rad);
}

/// Points re-expressed in the sensor frame at the sweep start (the mower moved during the sweep).
PointCloud deskew(const PointCloud& in, const std::function<Pose(double)>& pose_at, double t0,
                  const Pose& T_start) {
  PointCloud out = in;
  const Pose T_start_inv = T_start.inverse();
  for (auto& p : out.points) {
    if (!p.is_valid()) continue;
    const Eigen::Vector3d q =
        T_start_inv * (pose_at(t0 + double(p.time)) * Eigen::Vector3d(p.x, p.y, p.z));
    p.x = float(q.x());
    p.y = float(q.y());
    p.z = float(q.z());
  }
  return out;
}

}  // namespace

ClosedLoopResult run_closed_loop(const sim::Scene& scene, const SensorModel& sensor_in,
                                 const ClosedLoopConfig& cfg) {
  ClosedLoopResult res;
  SensorModel sensor = sensor_in;
  sensor.mounting_height_m = scene.sensor_height_m();
  sim::SimConfig sim_cfg;
  sim_cfg.seed = cfg.sim_seed;
  const sim::LidarSimulator lidar(scene, sensor, sim_cfg);
  FollowPipeline pipeline(sensor, cfg.follow);

  // Truth: the operator's loop.
  const sim::Walker* op = nullptr;
  for (const auto& w : scene.walkers())
    if (w.id() == cfg.operator_id) op = &w;
  if (op) res.operator_loop = op->config().path_m;
  double loop_length = 0;
  for (std::size_t i = 0; i < res.operator_loop.size(); ++i)
    loop_length +=
        (res.operator_loop[(i + 1) % res.operator_loop.size()] - res.operator_loop[i]).norm();
  const double speed = op ? std::max(0.3, op->speed_at(0)) : 1.0;
  const double max_time = cfg.max_time_s > 0 ? cfg.max_time_s : 1.6 * loop_length / speed + 20;

  // The mower starts at the start of the robot route, facing along it.
  Pose2 mower;
  const auto& route = scene.robot_route().size() >= 2 ? scene.robot_route() : res.operator_loop;
  if (route.size() >= 2) {
    mower.x_m = route[0].x();
    mower.y_m = route[0].y();
    mower.yaw_rad = std::atan2(route[1].y() - route[0].y(), route[1].x() - route[0].x());
  }
  const double period = sensor.sweep_period_s();
  const double b = cfg.follow.drive.track_width_m;
  WheelCommand cmd;
  double perception_total_ms = 0;
  std::optional<std::uint32_t> last_target;
  // Occlusion bookkeeping.
  int hidden_run = 0, occlusion_start = -1, resume_wait_from = -1;
  bool in_occlusion = false, stopped_in_occlusion = false;

  for (int k = 0; k * period < max_time; ++k) {
    const double t0 = k * period;
    const Pose2 start = mower;
    const double v = cmd.v_m_s, dv = cmd.dv_m_s;
    auto pose_at = [&](double t) {
      return lidar_pose(scene, predict_pose(start, v, dv, b, t - t0));
    };
    const auto frame = lidar.scan(t0, pose_at);
    const Pose T0 = pose_at(t0);
    const PointCloud cloud = deskew(frame.cloud, pose_at, t0, T0);
    // The command computed from this sweep applies from its end on.
    mower = predict_pose(start, v, dv, b, period);
    const auto tic = std::chrono::steady_clock::now();
    const auto out = pipeline.step(cloud, T0, mower, t0 + period / 2, period);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - tic).count();
    perception_total_ms += ms;
    cmd = out.control.command;

    LogRow row;
    row.t_s = t0 + period;
    row.mower_x = mower.x_m;
    row.mower_y = mower.y_m;
    row.mower_yaw = std::remainder(mower.yaw_rad, 2 * M_PI);
    if (out.target_world_m) {
      row.est_x = out.target_world_m->x();
      row.est_y = out.target_world_m->y();
    }
    for (const auto& p : frame.people)
      if (p.id == cfg.operator_id) row.target_points = p.points;
    for (const auto& p : scene.people_at(row.t_s))
      if (p.id == cfg.operator_id) {
        row.true_x = p.position_m.x();
        row.true_y = p.position_m.y();
      }
    row.true_distance_m = std::hypot(row.true_x - mower.x_m, row.true_y - mower.y_m);
    if (out.control.distance_m >= 0) row.distance_m = out.control.distance_m;
    row.wheel_left = cmd.left_m_s;
    row.wheel_right = cmd.right_m_s;
    row.state = out.control.state;
    row.target_id = out.target_id ? std::int64_t(*out.target_id) : -1;
    row.people_detected = out.perception.people_m.size();
    row.perception_ms = ms;
    res.rows.push_back(row);
    res.mower_path.push_back(mower.xy());

    // Metrics.
    if (cmd.moving() && row.true_distance_m < cfg.follow.safety.safe_distance_m)
      ++res.frames_moving_too_close;
    if (row.state == FollowState::kFollowing) {
      ++res.frames_following;
      if (out.target_world_m &&
          (*out.target_world_m - Eigen::Vector2d(row.true_x, row.true_y)).norm() > 0.5)
        ++res.frames_target_off;
    }
    if (out.target_id) {
      if (!res.first_target_id) res.first_target_id = out.target_id;
      if (last_target && *last_target != *out.target_id) ++res.target_switches;
      last_target = out.target_id;
    }
    // Occlusion: the operator returns no point for >= 2 consecutive sweeps once followed.
    if (res.first_target_id && row.target_points == 0) {
      if (++hidden_run == 1) occlusion_start = k;
      if (hidden_run == 2) {
        in_occlusion = true;
        stopped_in_occlusion = false;
        ++res.occlusions;
      }
      if (in_occlusion && !stopped_in_occlusion && !cmd.moving()) {
        stopped_in_occlusion = true;
        res.max_stop_delay_frames = std::max(res.max_stop_delay_frames, k - occlusion_start);
      }
    } else {
      if (in_occlusion) {
        if (!stopped_in_occlusion)
          res.max_stop_delay_frames = std::max(res.max_stop_delay_frames, 1000);
        resume_wait_from = k;
        in_occlusion = false;
      }
      hidden_run = 0;
      if (resume_wait_from >= 0 && cmd.moving()) {
        res.max_resume_delay_frames = std::max(res.max_resume_delay_frames, k - resume_wait_from);
        resume_wait_from = -1;
      }
    }

    // The stop command: the mower is back at the start of the recorded boundary.
    const auto& rec = pipeline.recorder();
    if (rec.length_m() > cfg.stop_fraction * loop_length && !rec.points().empty() &&
        (mower.xy() - rec.points().front()).norm() < cfg.stop_radius_m) {
      res.stopped_by_command = true;
      res.duration_s = row.t_s;
      break;
    }
    res.duration_s = row.t_s;
  }
  if (resume_wait_from >= 0) res.resumed_after_every_occlusion = false;
  if (in_occlusion) res.resumed_after_every_occlusion = false;
  res.boundary = pipeline.stop();
  res.boundary.closed = res.stopped_by_command;  // a time limit leaves the path open
  res.trail = pipeline.trail().points();
  res.boundary_error = compare_closed(res.boundary.vertices, res.operator_loop);
  res.mean_perception_ms = res.rows.empty() ? 0 : perception_total_ms / double(res.rows.size());
  return res;
}

std::string log_csv(const std::vector<LogRow>& rows) {
  std::string s =
      "t,mower_x,mower_y,mower_yaw,est_x,est_y,true_target_x,true_target_y,distance,"
      "true_distance,wheel_left,wheel_right,state,target_id,target_points,people_detected\n";
  char buf[512];
  for (const auto& r : rows) {
    std::snprintf(buf, sizeof buf,
                  "%.3f,%.4f,%.4f,%.5f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%s,%lld,%u,%zu\n",
                  r.t_s, r.mower_x, r.mower_y, r.mower_yaw, r.est_x, r.est_y, r.true_x, r.true_y,
                  r.distance_m, r.true_distance_m, r.wheel_left, r.wheel_right,
                  to_string(r.state).c_str(), static_cast<long long>(r.target_id), r.target_points,
                  r.people_detected);
    s += buf;
  }
  return s;
}

}  // namespace fieldlidar::loops
