#include "fieldlidar/sim/lidar_simulator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include <embree3/rtcore.h>

#include "ray_primitives.hpp"

namespace fieldlidar::sim {

namespace {

constexpr double kTwoPi = 2 * std::numbers::pi;

/// splitmix64: small, fast, good enough for sensor noise; seeded per sweep.
struct Rng {
  std::uint64_t state;
  bool has_spare = false;
  double spare = 0.0;
  std::uint64_t next() {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double uniform() { return double(next() >> 11) * 0x1.0p-53; }
  double normal() {
    if (has_spare) {
      has_spare = false;
      return spare;
    }
    const double u1 = std::max(uniform(), 1e-300), u2 = uniform();
    const double r = std::sqrt(-2.0 * std::log(u1));
    spare = r * std::sin(kTwoPi * u2);
    has_spare = true;
    return r * std::cos(kTwoPi * u2);
  }
};

/// Fraction of light returned at normal incidence per class (for the intensity channel).
double reflectivity(std::uint32_t label) {
  switch (label_class(label)) {
    case LabelClass::kGround:
      return 0.30;
    case LabelClass::kPerson:
      return 0.45;
    case LabelClass::kTrunk:
      return 0.35;
    case LabelClass::kVegetation:
      return 0.50;
    case LabelClass::kStructure:
      return 0.70;
    case LabelClass::kObstacle:
      return 0.25;
    default:
      return 0.30;
  }
}

struct EmbreeScene {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  EmbreeScene() = default;
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;
  ~EmbreeScene() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

}  // namespace

double column_azimuth_rad(const SensorModel& sensor, int column) {
  const double res = sensor.horizontal_resolution_rad();
  if (sensor.kind == SensorModel::Kind::kTilting2D)
    return -0.5 * sensor.horizontal_fov_rad + (column + 0.5) * res;  // right to left
  return std::numbers::pi - (column + 0.5) * res;                    // clockwise from behind
}

double firing_time_s(const SensorModel& sensor, int ring, int column) {
  const double period = sensor.sweep_period_s();
  if (sensor.kind == SensorModel::Kind::kTilting2D) {
    const double plane_period = period / double(sensor.rings());
    const double line_fraction = sensor.horizontal_fov_rad / kTwoPi;
    return plane_period * (ring + line_fraction * double(column) / sensor.columns);
  }
  return period * double(column) / sensor.columns;
}

Eigen::Vector3d beam_direction(const SensorModel& sensor, int ring, int column) {
  double az = column_azimuth_rad(sensor, column);
  const double el = sensor.beam_altitudes_rad[std::size_t(ring)];
  if (sensor.kind == SensorModel::Kind::kTilting2D) {
    // The 2D scan plane is pitched up by `el` about the lidar's y axis (nodding scanner).
    return {std::cos(az) * std::cos(el), std::sin(az), std::cos(az) * std::sin(el)};
  }
  if (!sensor.beam_azimuth_offsets_rad.empty())
    az += sensor.beam_azimuth_offsets_rad[std::size_t(ring)];
  return {std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)};
}

struct LidarSimulator::Impl {
  EmbreeScene embree;
  SensorModel sensor;
  SimConfig config;
  std::vector<std::uint32_t> labels;  // per static triangle
  std::vector<Walker> walkers;
  HeightField ground;
  // Beams in firing order: (ring, column), lidar-frame direction and origin, firing time.
  struct Beam {
    std::uint16_t ring;
    std::uint32_t column;
    float time_s;
    Eigen::Vector3f dir;
    Eigen::Vector3f origin;
  };
  std::vector<Beam> beams;

  std::vector<PersonBody> bodies_at(double t) const {
    std::vector<PersonBody> out;
    out.reserve(walkers.size());
    for (const auto& w : walkers) {
      Eigen::Vector2d xy, dir;
      w.path_point(w.arc_length_at(t), xy, dir);
      out.push_back(w.body_at(t, ground.height_at(xy)));
    }
    return out;
  }
};

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

  // Ray casting runs on the calling thread; one build thread keeps the shared machine quiet.
  im.embree.device = rtcNewDevice("threads=1");
  if (!im.embree.device) throw std::runtime_error("Embree: cannot create a device");
  im.embree.scene = rtcNewScene(im.embree.device);
  rtcSetSceneBuildQuality(im.embree.scene, RTC_BUILD_QUALITY_HIGH);
  const auto& mesh = scene.mesh();
  if (!mesh.empty()) {
    RTCGeometry geom = rtcNewGeometry(im.embree.device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0,
                                                          RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                          mesh.vertices.size()));
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
      v[3 * i] = mesh.vertices[i].x();
      v[3 * i + 1] = mesh.vertices[i].y();
      v[3 * i + 2] = mesh.vertices[i].z();
    }
    auto* idx = static_cast<std::uint32_t*>(
        rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                3 * sizeof(std::uint32_t), mesh.triangles.size()));
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
      for (int k = 0; k < 3; ++k) idx[3 * i + k] = mesh.triangles[i][k];
    rtcSetGeometryBuildQuality(geom, RTC_BUILD_QUALITY_HIGH);
    rtcCommitGeometry(geom);
    rtcAttachGeometry(im.embree.scene, geom);
    rtcReleaseGeometry(geom);
    im.labels = mesh.labels;
  }
  rtcCommitScene(im.embree.scene);
  if (rtcGetDeviceError(im.embree.device) != RTC_ERROR_NONE)
    throw std::runtime_error("Embree: building the scene failed");

  const int rings = static_cast<int>(sensor.rings());
  im.beams.reserve(std::size_t(rings) * sensor.columns);
  for (int c = 0; c < sensor.columns; ++c)
    for (int r = 0; r < rings; ++r) {
      Impl::Beam b;
      b.ring = static_cast<std::uint16_t>(r);
      b.column = static_cast<std::uint32_t>(c);
      b.time_s = static_cast<float>(firing_time_s(sensor, r, c));
      b.dir = beam_direction(sensor, r, c).cast<float>();
      const double az = column_azimuth_rad(sensor, c);
      b.origin = sensor.kind == SensorModel::Kind::kSpinning
                     ? Eigen::Vector3f(float(sensor.beam_origin_offset_m * std::cos(az)),
                                       float(sensor.beam_origin_offset_m * std::sin(az)), 0.f)
                     : Eigen::Vector3f::Zero();
      im.beams.push_back(b);
    }
  std::stable_sort(im.beams.begin(), im.beams.end(),
                   [](const Impl::Beam& a, const Impl::Beam& b) { return a.time_s < b.time_s; });
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
  rh.ray.org_x = float(origin_m.x());
  rh.ray.org_y = float(origin_m.y());
  rh.ray.org_z = float(origin_m.z());
  rh.ray.dir_x = float(d.x());
  rh.ray.dir_y = float(d.y());
  rh.ray.dir_z = float(d.z());
  rh.ray.tnear = 0.f;
  rh.ray.tfar = float(max_range_m);
  rh.ray.mask = ~0u;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  rtcIntersect1(impl_->embree.scene, &ctx, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
  const Eigen::Vector3d n = Eigen::Vector3d(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z).normalized();
  return Hit{rh.ray.tfar, impl_->labels[rh.hit.primID], n};
}

SimFrame LidarSimulator::scan(double t0_s, const std::function<Pose(double)>& T_world_lidar) const {
  const auto& im = *impl_;
  const auto& sensor = im.sensor;
  const auto& cfg = im.config;
  const int rings = static_cast<int>(sensor.rings());
  const int columns = sensor.columns;
  const std::size_t n = im.beams.size();

  Rng rng{cfg.seed * 0x9E3779B97F4A7C15ull ^ std::hash<double>{}(t0_s)};
  SimFrame frame;
  frame.stamp_s = t0_s;
  frame.T_world_lidar_start = T_world_lidar(t0_s);
  frame.T_world_lidar_end = T_world_lidar(t0_s + sensor.sweep_period_s());
  for (const auto& w : im.walkers) {
    auto p = w.truth_at(t0_s);
    p.visible_from_sensor_unknown = false;
    frame.people.push_back(p);
  }

  // Per beam result in (ring, column) layout.
  std::vector<Point> grid(std::size_t(rings) * columns);
  std::vector<std::uint32_t> grid_label(grid.size(), 0);
  std::vector<std::uint8_t> grid_valid(grid.size(), 0);

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
      RTCRayHit& rh = rays[k];
      rh.ray.org_x = float(o.x());
      rh.ray.org_y = float(o.y());
      rh.ray.org_z = float(o.z());
      rh.ray.dir_x = float(d.x());
      rh.ray.dir_y = float(d.y());
      rh.ray.dir_z = float(d.z());
      rh.ray.tnear = 0.f;
      rh.ray.tfar = float(sensor.max_range_m);
      rh.ray.time = 0.f;
      rh.ray.mask = ~0u;
      rh.ray.id = static_cast<unsigned>(k);
      rh.ray.flags = 0;
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
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
        for (const auto& body : body_sets[bodies_of_pose[pose_of_ray[k]]]) {
          if (!detail::ray_near_sphere(o, d, body.bound_center_m, body.bound_radius_m)) continue;
          for (const auto& part : body.parts) {
            Eigen::Vector3d nrm;
            const double t = detail::ray_capsule(o, d, part, nrm);
            if (t > 0 && t < range && t <= sensor.max_range_m) {
              range = t;
              label = make_label(LabelClass::kPerson, body.id);
              normal_world = nrm;
            }
          }
        }
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
      const std::size_t cell = std::size_t(b.ring) * columns + b.column;
      Point& out = grid[cell];
      out.x = p.x();
      out.y = p.y();
      out.z = p.z();
      out.intensity = cfg.intensity_from_incidence
                          ? float(std::clamp(255.0 * reflectivity(label) * cos_inc, 0.0, 255.0))
                          : float(255.0 * reflectivity(label));
      grid_label[cell] = label;
      grid_valid[cell] = 1;
      if (label_class(label) == LabelClass::kPerson)
        for (auto& p_truth : frame.people)
          if (p_truth.id == label_instance(label)) ++p_truth.points;
    }
  }

  // Every cell gets its ring and firing time, valid or not (organized output keeps them all).
  for (const auto& b : im.beams) {
    Point& p = grid[std::size_t(b.ring) * columns + b.column];
    p.ring = b.ring;
    p.time = b.time_s;
  }

  PointCloud& cloud = frame.cloud;
  cloud.stamp_s = t0_s;
  cloud.fields = PointFields{true, true, true, true};
  cloud.labels.reserve(grid.size());
  cloud.points.reserve(grid.size());
  if (cfg.order == PointOrder::kRingMajor) {
    for (std::size_t cell = 0; cell < grid.size(); ++cell)
      if (cfg.organized || grid_valid[cell]) {
        cloud.points.push_back(grid[cell]);
        cloud.labels.push_back(grid_label[cell]);
      }
  } else {
    for (const auto& b : im.beams) {
      const std::size_t cell = std::size_t(b.ring) * columns + b.column;
      if (cfg.organized || grid_valid[cell]) {
        cloud.points.push_back(grid[cell]);
        cloud.labels.push_back(grid_label[cell]);
      }
    }
  }
  if (cfg.organized) {
    cloud.width =
        cfg.order == PointOrder::kRingMajor ? std::uint32_t(columns) : std::uint32_t(rings);
    cloud.height =
        cfg.order == PointOrder::kRingMajor ? std::uint32_t(rings) : std::uint32_t(columns);
  } else {
    cloud.width = static_cast<std::uint32_t>(cloud.points.size());
    cloud.height = 1;
  }
  return frame;
}

}  // namespace fieldlidar::sim
