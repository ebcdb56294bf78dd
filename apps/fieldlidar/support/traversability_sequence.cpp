#include "support/traversability_sequence.hpp"

#include <chrono>
#include <memory>
#include <optional>

#include <fmt/core.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/frame_source.hpp"
#include "fieldlidar/io/trajectory_io.hpp"
#include "fieldlidar/odometry/deskew.hpp"
#include "fieldlidar/odometry/lidar_odometry.hpp"
#include "fieldlidar/segmentation/ground.hpp"
#include "fieldlidar/terrain/terrain_map.hpp"
#include "support/progress_line.hpp"
#include "support/sensor_choice.hpp"
#include "support/sweep_levelling.hpp"
#include "support/warnings.hpp"

namespace fieldlidar::app {

namespace {

/// A KITTI poses file (one pose per frame, by index) or else a TUM file (by stamp).
Trajectory read_poses(const std::string& path, bool& by_index) {
  try {
    by_index = true;
    return io::read_kitti_poses(path);
  } catch (const Error& kitti) {
    try {
      by_index = false;
      return io::read_tum(path);
    } catch (const Error& tum) {
      throw Error("--poses " + path + ": neither KITTI (" + kitti.what() + ") nor TUM (" +
                  tum.what() + ")");
    }
  }
}

}  // namespace

SequenceResult map_sequence(const SequenceOptions& o, const terrain::TraversabilityConfig& cfg) {
  SequenceResult r;
  bool by_index = true;
  Trajectory poses;
  if (!o.poses.empty()) poses = read_poses(o.poses, by_index);
  r.placed_by = o.poses.empty() ? "lidar odometry (first scan's frame, laid level)" : o.poses;
  terrain::FusionConfig fusion;
  fusion.layers = cfg;
  terrain::TerrainMap map(fusion);
  auto source = io::FrameSource::open(o.input);
  std::unique_ptr<odometry::LidarOdometry> odo;
  std::optional<Pose> T_level;  // placed by the odometry: its first scan's frame laid level
  std::optional<SensorModel> sensor;
  double last_stamp = -1e300;
  struct Placed {
    PointCloud cloud;
    Pose T;
  };
  std::optional<Placed> pending;
  const auto fuse = [&](Placed& p, const std::optional<Pose>& T_next, double dt_s) {
    if (p.cloud.fields.time && T_next) {
      const auto motion = odometry::SweepMotion::constant_velocity(p.T.inverse() * *T_next, dt_s);
      p.cloud = odometry::deskew(p.cloud, odometry::point_times(p.cloud, {}), motion);
      ++r.deskewed;
    }
    const auto t0 = std::chrono::steady_clock::now();
    map.add_scan(p.cloud, *sensor, p.T);
    r.update_ms +=
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  };
  ProgressLine progress;
  std::size_t frames_read = 0;
  while (auto frame = source->next()) {
    frames_read = frame->index + 1;
    PointCloud& cloud = frame->cloud;
    if (const auto why = segmentation::implausible_span(cloud))
      throw Error(fmt::format("{}: frame {}: {}", o.input, frame->index, *why));
    drop_nearer_than(cloud, o.min_range_m);
    if (!sensor) {
      sensor = source->sensor() ? *source->sensor() : sensor_for(cloud, o.input, o.sensor);
      r.sensor = sensor->name;
    }
    if (cloud.stamp_s <= 0 && frame->index > 0)  // files without a clock: a sweep apart
      cloud.stamp_s = frame->index * sensor->sweep_period_s();
    std::optional<Pose> T;
    if (!o.poses.empty()) {
      if (by_index && frame->index >= poses.size())
        throw Error(fmt::format("--poses {}: {} poses, but frame {} of {} has none", o.poses,
                                poses.size(), frame->index, o.input));
      T = by_index ? std::optional<Pose>(poses[frame->index].pose) : poses.at(cloud.stamp_s);
    } else {
      if (!odo) {
        odometry::OdometryConfig ocfg;
        ocfg.expected_period_s = sensor->sweep_period_s();
        odo = std::make_unique<odometry::LidarOdometry>(*sensor, ocfg);
      }
      // A sensor mounted tilted or upside down: the map is laid level by the rotation that
      // levels the first scan (said once), not in its tilted frame.
      if (!T_level) T_level = levelling_pose(cloud, cfg.ground.levelling, o.input);
      T = *T_level * odo->register_frame(cloud).T_world_lidar;
    }
    if (!T) {  // a TUM trajectory that does not cover this frame's stamp
      ++r.skipped;
      continue;
    }
    // Each sweep is fused once the next one is placed: with per-point times, it is re-projected
    // onto its start pose at the constant velocity between the two poses (taken up to 1 s apart).
    if (pending) {
      const double dt_s = cloud.stamp_s - pending->cloud.stamp_s;
      fuse(*pending, dt_s > 0 && dt_s <= 1.0 ? std::optional<Pose>(*T) : std::nullopt, dt_s);
    }
    pending = Placed{std::move(cloud), *T};
    ++r.frames;
    const double stamp =
        pending->cloud.stamp_s > last_stamp ? pending->cloud.stamp_s : last_stamp + 1e-6;
    last_stamp = stamp;
    r.path.push_back(stamp, *T);
    if (frame->index % 20 == 0)
      progress.show("frame {} ({:.0f} %)   ", frame->index, 100 * source->progress());
  }
  if (pending) fuse(*pending, std::nullopt, 0.0);  // the last sweep, its motion unknown
  progress.end();
  warn_source_losses(*source);
  // More poses than frames: the poses are of another sequence (or another cut of this one).
  if (!o.poses.empty() && by_index && poses.size() != frames_read)
    throw Error(
        fmt::format("--poses {}: {} poses for the {} frames of {}: not the poses of this "
                    "sequence",
                    o.poses, poses.size(), frames_read, o.input));
  if (r.frames == 0)
    throw Error(o.input + ": no frame could be placed" +
                (o.poses.empty() ? std::string() : " by --poses " + o.poses));
  r.map = map.global_map();
  return r;
}

}  // namespace fieldlidar::app
