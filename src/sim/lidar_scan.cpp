// LidarSimulator::scan: one sweep, every beam cast from the pose at its own firing time.
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "beam_grid.hpp"
#include "noise_rng.hpp"
#include "ray_primitives.hpp"
#include "reflectivity.hpp"
#include "simulator_state.hpp"

namespace fieldlidar::sim {

namespace {

/// Moves (range, label, normal) to the nearest hit of the ray (o, d) with the people's capsules
/// when one is closer than `range` and within `max_range_m`.
void intersect_people(const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                      const std::vector<PersonBody>& bodies, double max_range_m, double& range,
                      std::uint32_t& label, Eigen::Vector3d& normal) {
  for (const auto& body : bodies) {
    if (!detail::ray_near_sphere(o, d, body.bound_center_m, body.bound_radius_m)) continue;
    for (const auto& part : body.parts) {
      Eigen::Vector3d nrm;
      const double t = detail::ray_capsule(o, d, part, nrm);
      if (t > 0 && t < range && t <= max_range_m) {
        range = t;
        label = make_label(LabelClass::kPerson, body.id);
        normal = nrm;
      }
    }
  }
}

}  // namespace

SimFrame LidarSimulator::scan(double t0_s, const std::function<Pose(double)>& T_world_lidar) const {
  const auto& im = *impl_;
  const auto& sensor = im.sensor;
  const auto& cfg = im.config;
  const std::size_t n = im.beams.size();

  detail::NoiseRng rng{cfg.seed * 0x9E3779B97F4A7C15ull ^ std::hash<double>{}(t0_s)};
  SimFrame frame;
  frame.stamp_s = t0_s;
  frame.T_world_lidar_start = T_world_lidar(t0_s);
  frame.T_world_lidar_end = T_world_lidar(t0_s + sensor.sweep_period_s());
  for (const auto& w : im.walkers) {
    auto p = w.truth_at(t0_s);
    p.visible_from_sensor_unknown = false;
    frame.people.push_back(p);
  }

  detail::BeamGrid grid(static_cast<int>(sensor.rings()), sensor.columns);

  constexpr std::size_t kChunk = 1024;
  std::vector<RTCRayHit> rays(kChunk);
  std::vector<std::uint32_t> pose_of_ray(kChunk);  // index into poses (one per firing time)
  std::vector<Pose> poses;
  std::vector<std::uint32_t> bodies_of_pose;  // index into body_sets
  std::vector<std::vector<PersonBody>> body_sets;
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  const bool people = cfg.simulate_people && !im.walkers.empty();
  double body_time = -1e300;
  std::vector<PersonBody> current_bodies;

  for (std::size_t start = 0; start < n; start += kChunk) {
    const std::size_t m = std::min(kChunk, n - start);
    poses.clear();
    bodies_of_pose.clear();
    body_sets.clear();
    if (people) body_sets.push_back(current_bodies);
    float last_time = std::numeric_limits<float>::quiet_NaN();
    for (std::size_t k = 0; k < m; ++k) {
      const auto& b = im.beams[start + k];
      if (!(b.time_s == last_time)) {
        last_time = b.time_s;
        const double t = t0_s + b.time_s;
        poses.push_back(T_world_lidar(t));
        if (!poses.back().matrix().allFinite())
          throw std::invalid_argument("LidarSimulator::scan: T_world_lidar(" + std::to_string(t) +
                                      ") is not finite");
        // People move at most ~2 m/s: re-posing them every 0.5 ms keeps them within 1 mm.
        if (people && std::abs(t - body_time) > 5e-4) {
          current_bodies = im.bodies_at(t);
          body_time = t;
          body_sets.push_back(current_bodies);
        }
        bodies_of_pose.push_back(people ? std::uint32_t(body_sets.size() - 1) : 0u);
      }
      pose_of_ray[k] = static_cast<std::uint32_t>(poses.size() - 1);
      const Pose& T = poses.back();
      const Eigen::Vector3d o = T * b.origin.cast<double>();
      const Eigen::Vector3d d = T.linear() * b.dir.cast<double>();
      detail::set_ray(rays[k], o, d, float(sensor.max_range_m), static_cast<unsigned>(k));
    }
    rtcIntersect1M(im.embree.scene, &ctx, rays.data(), static_cast<unsigned>(m), sizeof(RTCRayHit));

    for (std::size_t k = 0; k < m; ++k) {
      const auto& b = im.beams[start + k];
      const RTCRayHit& rh = rays[k];
      double range = std::numeric_limits<double>::infinity();
      std::uint32_t label = 0;
      Eigen::Vector3d normal_world = Eigen::Vector3d::UnitZ();
      if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
        range = rh.ray.tfar;
        label = im.labels[rh.hit.primID];
        normal_world = Eigen::Vector3d(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
      }
      if (people) {
        const Eigen::Vector3d o(rh.ray.org_x, rh.ray.org_y, rh.ray.org_z);
        const Eigen::Vector3d d = Eigen::Vector3d(rh.ray.dir_x, rh.ray.dir_y, rh.ray.dir_z);
        intersect_people(o, d, body_sets[bodies_of_pose[pose_of_ray[k]]], sensor.max_range_m, range,
                         label, normal_world);
      }
      if (!std::isfinite(range) || range < sensor.min_range_m) continue;
      const Eigen::Vector3d d_world = poses[pose_of_ray[k]].linear() * b.dir.cast<double>();
      const double n2 = normal_world.squaredNorm();
      const double cos_inc = n2 > 0 ? std::abs(normal_world.dot(d_world)) / std::sqrt(n2) : 1.0;
      if (cos_inc < cfg.grazing_dropout_cos) continue;
      if (cfg.dropout_probability > 0 && rng.uniform() < cfg.dropout_probability) continue;
      const double r = cfg.range_noise_m > 0 ? range + cfg.range_noise_m * rng.normal() : range;
      if (r < sensor.min_range_m || r > sensor.max_range_m) continue;
      // The point in the lidar frame at its own firing time: the beam origin plus the measured
      // range along the beam, exactly as the sensor reports it (no motion compensation).
      const Eigen::Vector3f p = b.origin + float(r) * b.dir;
      const std::size_t cell = grid.cell(b);
      Point& out = grid.points[cell];
      out.x = p.x();
      out.y = p.y();
      out.z = p.z();
      const double reflect = detail::reflectivity(label);
      out.intensity = cfg.intensity_from_incidence
                          ? float(std::clamp(255.0 * reflect * cos_inc, 0.0, 255.0))
                          : float(255.0 * reflect);
      grid.labels[cell] = label;
      grid.valid[cell] = 1;
      if (label_class(label) == LabelClass::kPerson)
        for (auto& p_truth : frame.people)
          if (p_truth.id == label_instance(label)) ++p_truth.points;
    }
  }

  detail::grid_to_cloud(grid, im.beams, cfg, t0_s, frame.cloud);
  return frame;
}

}  // namespace fieldlidar::sim
