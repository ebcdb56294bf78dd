// The seed 000 follow loop driven by the simulator, the mower's pose from LiDAR odometry (or the
// truth), and its figures against the truth.

#include "fieldlidar/loops/closed_loop.hpp"

#include <chrono>
#include <cmath>

#include "fieldlidar/follow/replay.hpp"
#include "fieldlidar/sim/lidar_simulator.hpp"

namespace fieldlidar::loops {

using follow::compare_closed;
using follow::FollowPipeline;
using follow::FollowState;
using follow::Pose2;
using follow::WheelCommand;

namespace {

/// The mower's base resting on the ground under its wheels (pitched and rolled with it).
Pose base_pose(const sim::Scene& scene, const Pose2& m) {
  return sim::pose_on_ground(scene, m.xy(), m.yaw_rad);
}

/// The sensor on its mast, straight up from the base.
Pose lidar_pose(const sim::Scene& scene, const Pose2& m) {
  return base_pose(scene, m) * make_pose(0, 0, scene.sensor_height_m(), 0, 0, 0);
}

/// A planar pose at height 0.
Pose flat_pose(const Pose2& m) {
  return make_pose(m.x_m, m.y_m, 0, 0, 0, m.yaw_rad);
}

/// A world position in the recording frame (the frames differ by a turn about z and a shift).
Eigen::Vector2d in_frame(const Pose& T_frame_world, const Eigen::Vector2d& p) {
  return (T_frame_world * Eigen::Vector3d(p.x(), p.y(), 0)).head<2>();
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
  const double period = sensor.sweep_period_s();
  const double b = cfg.follow.drive.track_width_m;
  res.pose_source = cfg.pose_source;
  const bool planar_laser = sensor.kind == SensorModel::Kind::kPlanar2D;
  std::optional<people::LegPipeline2D> legs_2d;
  if (planar_laser) legs_2d.emplace(cfg.legs_2d);
  std::optional<DeadReckoningPoseSource> dead_reckoning;
  if (cfg.pose_source == PoseSource::kOdometry && planar_laser) {
    MotionStreamsConfig streams = cfg.streams;
    streams.wheels.track_width_m = b;
    dead_reckoning.emplace(streams);
  }
  std::optional<OdometryPoseSource> odometry;
  if (cfg.pose_source == PoseSource::kOdometry && !planar_laser) {
    MotionStreamsConfig streams = cfg.streams;
    streams.wheels.track_width_m = b;
    odometry.emplace(sensor, scene.sensor_height_m(), cfg.odometry, streams);
  }
  // The recording frame: the world with true poses, the first sweep's lidar pose with odometry.
  Pose T_frame_world = Pose::Identity();

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
  WheelCommand cmd;
  double perception_total_ms = 0, odometry_total_ms = 0;
  MowerSegment previous;
  std::optional<std::uint32_t> last_target;
  // Occlusion bookkeeping.
  int hidden_run = 0, occlusion_start = -1, resume_wait_from = -1;
  bool in_occlusion = false, stopped_in_occlusion = false;

  for (int k = 0; k * period < max_time; ++k) {
    const double t0 = k * period;
    const double v = cmd.v_m_s, dv = cmd.dv_m_s;
    const MowerSegment segment{mower, t0, v, dv, b};
    if (k == 0) previous = segment;
    auto pose_at = [&](double t) { return lidar_pose(scene, segment.at(t)); };
    const auto frame = lidar.scan(t0, pose_at);
    const Pose T0 = pose_at(t0);
    // The command computed from this sweep applies from its end on.
    mower = follow::predict_pose(mower, v, dv, b, period);

    // The pose the pipeline works with: the lidar at the sweep start and the mower at its end.
    Pose T0_used = T0;
    Pose2 mower_used = mower;
    PointCloud cloud;
    LogRow row;
    if (dead_reckoning) {
      // The wheels and IMU give a level frame: the first lidar pose's position and heading.
      if (k == 0) {
        const Eigen::Vector3d o = T0.translation();
        T_frame_world = make_pose(o.x(), o.y(), o.z(), 0, 0, yaw_of(T0)).inverse();
      }
      T0_used = flat_pose(dead_reckoning->pose());
      const MowerSegment relative{{}, t0, v, dv, b};
      cloud = deskew(
          frame.cloud, [&](double t) { return flat_pose(relative.at(t)); }, t0, Pose::Identity());
      mower_used = dead_reckoning->advance(
          [&](double t) { return base_pose(scene, segment.at(t)); }, t0, t0 + period);
    } else if (!odometry) {
      cloud = deskew(frame.cloud, pose_at, t0, T0);
    } else {
      if (k == 0) T_frame_world = T0.inverse();
      // The streams the mower records while it drives this period (the IMU's finite differences
      // reach into the previous one).
      odometry->add_streams(
          [&](double t) { return base_pose(scene, (t < t0 ? previous : segment).at(t)); }, t0,
          t0 + period);
      const auto tic = std::chrono::steady_clock::now();
      const auto r = odometry->register_sweep(frame.cloud);
      row.odometry_ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - tic).count();
      odometry_total_ms += row.odometry_ms;
      row.odometry_registered = r.registered || k == 0;
      res.odometry_unregistered += !row.odometry_registered;
      res.odometry_degenerate += r.degenerate;
      T0_used = r.T_world_lidar;
      // The wheel odometry the loop has: the commanded speeds carry the pose over the sweep and
      // re-project its points onto the sweep start.
      const MowerSegment relative{{}, t0, v, dv, b};
      cloud = deskew(
          frame.cloud, [&](double t) { return flat_pose(relative.at(t)); }, t0, Pose::Identity());
      mower_used = follow::predict_pose(planar(T0_used), v, dv, b, period);
    }
    previous = segment;
    const auto tic = std::chrono::steady_clock::now();
    follow::FrameOutput out;
    if (planar_laser) {
      // The 2D leg pipeline: legs, leg tracks and persons in the recording frame.
      out = pipeline.follow(follow::perceive_2d(*legs_2d, t0, cloud, T0_used, true), mower_used,
                            t0 + period / 2, period);
    } else {
      out = pipeline.step(cloud, T0_used, mower_used, t0 + period / 2, period);
    }
    res.lidar_poses_used.push_back(T0_used);
    res.lidar_poses_true.push_back(T_frame_world * T0);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - tic).count();
    perception_total_ms += ms;
    cmd = out.control.command;

    row.t_s = t0 + period;
    const Eigen::Vector2d mower_xy = in_frame(T_frame_world, mower.xy());
    row.mower_x = mower_xy.x();
    row.mower_y = mower_xy.y();
    row.mower_yaw = std::remainder(mower.yaw_rad + yaw_of(T_frame_world), 2 * M_PI);
    row.mower_est_x = mower_used.x_m;
    row.mower_est_y = mower_used.y_m;
    row.mower_est_yaw = std::remainder(mower_used.yaw_rad, 2 * M_PI);
    if (out.target_world_m) {
      row.est_x = out.target_world_m->x();
      row.est_y = out.target_world_m->y();
    }
    for (const auto& p : frame.people)
      if (p.id == cfg.operator_id) row.target_points = p.points;
    for (const auto& p : scene.people_at(row.t_s))
      if (p.id == cfg.operator_id) {
        const Eigen::Vector2d q = in_frame(T_frame_world, p.position_m);
        row.true_x = q.x();
        row.true_y = q.y();
      }
    row.true_distance_m = std::hypot(row.true_x - row.mower_x, row.true_y - row.mower_y);
    if (out.control.distance_m >= 0) row.distance_m = out.control.distance_m;
    row.wheel_left = cmd.left_m_s;
    row.wheel_right = cmd.right_m_s;
    row.state = out.control.state;
    row.target_id = out.target_id ? std::int64_t(*out.target_id) : -1;
    row.people_detected = out.perception.people_m.size();
    row.perception_ms = ms;
    res.rows.push_back(row);
    res.mower_path.push_back(mower_xy);

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
      ++res.frames_target_chosen;
      res.frames_target_held += out.target_world_m.has_value();
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
        (mower_used.xy() - rec.points().front()).norm() < cfg.stop_radius_m) {
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
  for (auto& p : res.operator_loop) p = in_frame(T_frame_world, p);
  res.T_world_frame = T_frame_world.inverse();
  res.boundary_error = compare_closed(res.boundary.vertices, res.operator_loop);
  const double frames = std::max<double>(1.0, double(res.rows.size()));
  res.mean_perception_ms = perception_total_ms / frames;
  if (odometry || dead_reckoning) {
    res.mean_odometry_ms = odometry_total_ms / frames;
    if (res.lidar_poses_used.size() >= 2)
      res.odometry_accuracy = evaluate_trajectory(res.lidar_poses_used, res.lidar_poses_true);
  }
  return res;
}

}  // namespace fieldlidar::loops
