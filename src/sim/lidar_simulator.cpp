// LidarSimulator: building the simulator (scene BVH, beam table), single rays; the sweep itself
// is in lidar_scan.cpp.
#include "fieldlidar/sim/lidar_simulator.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "simulator_state.hpp"

namespace fieldlidar::sim {

namespace detail {

std::vector<SimBeam> beams_in_firing_order(const SensorModel& sensor) {
  const int rings = static_cast<int>(sensor.rings());
  std::vector<SimBeam> beams;
  beams.reserve(std::size_t(rings) * sensor.columns);
  for (int c = 0; c < sensor.columns; ++c)
    for (int r = 0; r < rings; ++r) {
      SimBeam b;
      b.ring = static_cast<std::uint16_t>(r);
      b.column = static_cast<std::uint32_t>(c);
      b.time_s = static_cast<float>(firing_time_s(sensor, r, c));
      b.dir = beam_direction(sensor, r, c).cast<float>();
      const double az = column_azimuth_rad(sensor, c);
      b.origin = sensor.kind == SensorModel::Kind::kSpinning
                     ? Eigen::Vector3f(float(sensor.beam_origin_offset_m * std::cos(az)),
                                       float(sensor.beam_origin_offset_m * std::sin(az)), 0.f)
                     : Eigen::Vector3f::Zero();
      beams.push_back(b);
    }
  std::stable_sort(beams.begin(), beams.end(),
                   [](const SimBeam& a, const SimBeam& b) { return a.time_s < b.time_s; });
  return beams;
}

}  // namespace detail

LidarSimulator::LidarSimulator(const Scene& scene, const SensorModel& sensor,
                               const SimConfig& config)
    : impl_(std::make_unique<Impl>()) {
  sensor.validate();
  if (!(config.dropout_probability >= 0 && config.dropout_probability <= 1))
    throw std::invalid_argument("SimConfig.dropout_probability must be in [0, 1]");
  auto& im = *impl_;
  im.sensor = sensor;
  im.config = config;
  if (im.config.range_noise_m < 0) im.config.range_noise_m = sensor.range_accuracy_m;
  im.walkers = scene.walkers();
  im.ground = scene.ground();
  detail::build_embree_scene(scene.mesh(), im.embree);
  im.labels = scene.mesh().labels;
  im.beams = detail::beams_in_firing_order(sensor);
}

LidarSimulator::~LidarSimulator() = default;
LidarSimulator::LidarSimulator(LidarSimulator&&) noexcept = default;
LidarSimulator& LidarSimulator::operator=(LidarSimulator&&) noexcept = default;

const SensorModel& LidarSimulator::sensor() const {
  return impl_->sensor;
}
const SimConfig& LidarSimulator::config() const {
  return impl_->config;
}

SimFrame LidarSimulator::scan(double t0_s, const Pose& T_world_lidar) const {
  return scan(t0_s, [&](double) { return T_world_lidar; });
}

std::optional<LidarSimulator::Hit> LidarSimulator::cast(const Eigen::Vector3d& origin_m,
                                                        const Eigen::Vector3d& direction,
                                                        double max_range_m) const {
  const Eigen::Vector3d d = direction.normalized();
  RTCRayHit rh{};
  detail::set_ray(rh, origin_m, d, float(max_range_m), 0);
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  rtcIntersect1(impl_->embree.scene, &ctx, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
  const Eigen::Vector3d n = Eigen::Vector3d(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z).normalized();
  return Hit{rh.ray.tfar, impl_->labels[rh.hit.primID], n};
}

}  // namespace fieldlidar::sim
