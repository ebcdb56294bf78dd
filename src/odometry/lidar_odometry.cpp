// seed 002, steps a-f: one sweep after the other, de-skewed, split, reduced to features, matched
// against the local map (or the previous sweep) and added to the map.

#include "fieldlidar/odometry/lidar_odometry.hpp"

#include <chrono>
#include <cmath>

#include <fmt/core.h>

#include "fieldlidar/core/error.hpp"

namespace fieldlidar::odometry {

namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

std::vector<Eigen::Vector3f> to_world(std::span<const Eigen::Vector3f> pts, const Pose& T) {
  const Eigen::Matrix3f R = T.linear().cast<float>();
  const Eigen::Vector3f t = T.translation().cast<float>();
  std::vector<Eigen::Vector3f> out;
  out.reserve(pts.size());
  for (const auto& p : pts) out.push_back(R * p + t);
  return out;
}

std::size_t count_non_finite(const PointCloud& cloud) {
  std::size_t n = 0;
  for (const auto& p : cloud.points)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) ++n;
  return n;
}

}  // namespace

LidarOdometry::LidarOdometry(const SensorModel& sensor, const OdometryConfig& config)
    : sensor_(sensor), config_(config), map_(config.map) {}

void LidarOdometry::set_map(LocalMap map, const Pose& T_world_lidar_initial) {
  // Either would leave every frame unregistered (or NaN) without a word.
  if (map.size() == 0) throw Error("localisation: the map has no points");
  if (!T_world_lidar_initial.matrix().allFinite())
    throw Error("localisation: the initial pose is not finite (NaN or inf)");
  map_ = std::move(map);
  T_world_lidar_ = T_world_lidar_initial;
  config_.update_map = false;
}

OdometryResult LidarOdometry::register_frame(const PointCloud& cloud) {
  const auto t_start = Clock::now();
  OdometryResult result;
  if (const auto bad = count_non_finite(cloud); bad > 0)
    result.warnings.push_back(fmt::format("{} points with NaN/inf coordinates ignored", bad));

  // a. de-skew with the motion predicted from IMU + wheels, else a constant velocity.
  auto t = Clock::now();
  const Prior prior = predict(cloud.stamp_s, result.warnings);
  result.motion_source = prior.source;
  // The sweep is registered at its reference time (mid-sweep or start), T_start_ref apart.
  const bool skew = config_.deskew.enabled && !prior.sweep.empty();
  const double t_ref = skew && prior.sweep_from_velocity && config_.deskew.mid_sweep_reference
                           ? 0.5 * prior.sweep.last_time_s()
                           : 0.0;
  const Pose T_start_ref = skew ? prior.sweep.at(t_ref) : Pose::Identity();
  // The sensor's own geometry first (an intrinsic correction), then the motion.
  PointCloud corrected;
  const PointCloud* raw = &cloud;
  if (config_.preprocess.elevation_correction_deg != 0.0) {
    corrected = cloud;
    correct_elevation(corrected, config_.preprocess.elevation_correction_deg * M_PI / 180.0);
    raw = &corrected;
  }
  const PointCloud swept =
      skew ? deskew(*raw, point_times(*raw, config_.deskew), prior.sweep, t_ref) : *raw;
  result.timings.deskew_ms = ms_since(t);

  // b, c. rings, ground, clusters; curvature features.
  t = Clock::now();
  const Preprocessed pre = preprocess(swept, sensor_, config_.preprocess);
  result.timings.preprocess_ms = ms_since(t);
  t = Clock::now();
  const Features features =
      extract_features(swept, pre.rings, pre.allowed, pre.ground, config_.features);
  // The features matched: the selected ones, thinned by spacing (LOAM's mapping stage).
  Features thinned;
  const double edge_spacing = config_.features.match_edge_spacing_m;
  const double plane_spacing = config_.features.match_plane_spacing_m;
  if (edge_spacing > 0 || plane_spacing > 0) {
    thinned.edges = features.edges;
    thinned.planes = features.planes;
    thin_by_spacing(thinned.edges, edge_spacing);
    thin_by_spacing(thinned.planes, plane_spacing);
  }
  const Features& matched = edge_spacing > 0 || plane_spacing > 0 ? thinned : features;
  result.edge_features = matched.edges.size();
  result.plane_features = matched.planes.size();
  result.timings.features_ms = ms_since(t);

  // d. match against the local map (or the previous sweep) by Levenberg-Marquardt.
  t = Clock::now();
  const Pose prior_ref = prior.T_world_lidar * T_start_ref;
  result.T_world_lidar = prior_ref;
  const Pose step = T_world_lidar_.inverse() * prior.T_world_lidar;
  result.stationary =
      initialised_ && config_.stationary_m > 0 &&
      (prior.source == MotionSource::kImuWheels || prior.source == MotionSource::kWheels) &&
      step.translation().norm() < config_.stationary_m &&
      Eigen::AngleAxisd(step.linear()).angle() < config_.stationary_m;
  if (result.stationary) {
    // The last pose itself: the IMU's gyro bias would turn a standing robot slowly.
    result.registered = true;
    result.T_world_lidar = T_world_ref_;
  } else if (!map_.empty()) {
    register_features(matched, features, prior_ref, result);
  }
  result.timings.match_ms = ms_since(t);

  // e. into the world frame: the map grows.
  t = Clock::now();
  const bool first = !initialised_;
  const Pose T_world_ref = result.T_world_lidar;
  if (result.registered || first) update_map(features, T_world_ref);
  result.timings.map_ms = ms_since(t);

  // Motion for the next prediction, between reference poses (they do not depend on the de-skew
  // velocity); the pose reported is the sweep start's.
  result.T_world_lidar = T_world_ref * T_start_ref.inverse();
  const bool first_velocity = initialised_ && !velocity_known_;
  if (initialised_) {
    const double dt = cloud.stamp_s - last_stamp_s_;
    if (velocity_known_) T_prev_delta_ = T_last_delta_, prev_period_s_ = last_period_s_;
    T_last_delta_ = T_world_ref_.inverse() * T_world_ref;
    last_period_s_ = dt > 0 ? dt : config_.expected_period_s;
    velocity_known_ = true;
  }
  T_world_ref_ = T_world_ref;
  T_world_lidar_ = result.T_world_lidar;
  if (first && config_.update_map && velocity_deskews(*raw)) {
    first_sweep_ = *raw;
    T_world_first_ = T_world_lidar_;
  }
  if (first_velocity && first_sweep_ && result.registered) {
    t = Clock::now();
    rebuild_map_deskewed(*raw);
    result.timings.map_ms += ms_since(t);
  }
  if (first_velocity) first_sweep_.reset();
  if (!initialised_ || cloud.stamp_s > last_stamp_s_) last_stamp_s_ = cloud.stamp_s;
  initialised_ = true;
  ++frames_;
  trim_streams(last_stamp_s_ - 1.0);
  result.timings.total_ms = ms_since(t_start);
  return result;
}

void LidarOdometry::register_features(const Features& matched, const Features& all,
                                      const Pose& prior, OdometryResult& result) {
  Pose T = prior;
  double first_fraction = 1.0;
  bool ok = match_rounds(map_, matched, T, result, &first_fraction);
  result.prior_match_fraction = first_fraction;
  // A prior far off (a fast turn, skipped frames, a rough start in a saved map): few features
  // find a line or plane near them. Align on a coarse copy of the map first, then again.
  double used_fraction = first_fraction;
  const bool unusual = typical_match_fraction_ < 0 ||
                       first_fraction < config_.coarse_below_typical * typical_match_fraction_;
  const std::size_t n = all.edges.size() + all.planes.size();
  if (config_.coarse_voxel_m > 0 && first_fraction < config_.coarse_below_fraction && unusual &&
      n > 0) {
    // The re-alignment takes every selected feature: the thinned ones alone missed the largest
    // turns of the simulated handheld sweep, whose dense ground pulls the coarse alignment in.
    // The gain is counted against the fraction of them all at the prior; without one, the
    // thinned features' pose stands.
    const double all_fraction =
        &matched != &all ? match_fraction(map_, all, prior) : first_fraction;
    LocalMapConfig cc = config_.map;
    cc.voxel_m = config_.coarse_voxel_m;
    cc.max_neighbour_distance_m = 0.5 * config_.coarse_voxel_m;
    cc.min_point_spacing_m = 0.25 * config_.coarse_voxel_m / 4;
    cc.max_points_per_voxel = 4 * config_.map.max_points_per_voxel;
    cc.max_plane_distance_m = 2 * config_.map.max_plane_distance_m;
    const LocalMap coarse = LocalMap::from_cloud(map_.to_cloud(), cc);
    Pose Tc = prior;
    OdometryResult scratch;  // the coarse alignment's diagnostics are not the frame's
    if (match_rounds(coarse, all, Tc, scratch, nullptr)) {
      Pose Tf = Tc;
      double fraction = 0;
      OdometryResult retry = result;
      if (match_rounds(map_, all, Tf, retry, &fraction) &&
          fraction > all_fraction + config_.coarse_min_gain) {
        retry.warnings.push_back(fmt::format(
            "prior {:.2f} m / {:.1f} deg off: re-aligned on the coarse map",
            (Tf.translation() - prior.translation()).norm(),
            Eigen::AngleAxisd(Tf.linear() * prior.linear().transpose()).angle() * 180 / M_PI));
        retry.edge_features = all.edges.size();
        retry.plane_features = all.planes.size();
        result = std::move(retry);
        result.prior_match_fraction = first_fraction;
        result.coarse_realigned = true;
        used_fraction = fraction;
        T = Tf;
        ok = true;
      }
    }
  }
  if (!ok) {
    result.warnings.push_back(
        fmt::format("{} feature matches (< {}): too few features, pose from the motion prior",
                    result.inliers, config_.min_matches));
    result.registered = false;
    result.T_world_lidar = prior;
    return;
  }
  result.T_world_lidar = T;
  typical_match_fraction_ =
      typical_match_fraction_ < 0
          ? used_fraction
          : typical_match_fraction_ + 0.2 * (used_fraction - typical_match_fraction_);
}

double LidarOdometry::match_fraction(const LocalMap& map, const Features& features, const Pose& T) {
  const std::size_t n = features.edges.size() + features.planes.size();
  if (n == 0) return 0.0;
  const Eigen::Matrix3f R = T.linear().cast<float>();
  const Eigen::Vector3f tr = T.translation().cast<float>();
  std::size_t found = 0;
  for (const auto& p : features.edges) found += map.match_edge(R * p + tr).has_value();
  for (const auto& p : features.planes) found += map.match_plane(R * p + tr).has_value();
  return double(found) / double(n);
}

bool LidarOdometry::match_rounds(const LocalMap& map, const Features& features, Pose& T,
                                 OdometryResult& result, double* first_fraction) const {
  std::vector<Correspondence> matches;
  // Each query's match and where (world) it was looked up: a query that moved less than
  // reassociate_m since keeps its line or plane (a miss stays a miss).
  const std::size_t n_edges = features.edges.size();
  const std::size_t n = n_edges + features.planes.size();
  std::vector<std::optional<Correspondence>> cache(n);
  std::vector<Eigen::Vector3f> looked_up(n);
  const float reassociate2 = float(config_.reassociate_m * config_.reassociate_m);
  bool registered = false;
  for (int round = 0; round < config_.max_associations; ++round) {
    matches.clear();
    const Eigen::Matrix3f R = T.linear().cast<float>();
    const Eigen::Vector3f tr = T.translation().cast<float>();
    for (std::size_t i = 0; i < n; ++i) {
      const bool edge = i < n_edges;
      const Eigen::Vector3f& p = edge ? features.edges[i] : features.planes[i - n_edges];
      const Eigen::Vector3f q = R * p + tr;
      if (round == 0 || (q - looked_up[i]).squaredNorm() > reassociate2) {
        cache[i] = edge ? map.match_edge(q) : map.match_plane(q);
        looked_up[i] = q;
      }
      if (cache[i]) {
        matches.push_back(*cache[i]);
        matches.back().point_lidar = p.cast<double>();
      }
    }
    if (round == 0 && first_fraction)
      *first_fraction = n > 0 ? double(matches.size()) / double(n) : 0.0;
    result.inliers = matches.size();
    if (int(matches.size()) < config_.min_matches) return registered;
    const LmResult lm = solve_lm(matches, T, config_.lm);
    result.iterations += lm.iterations;
    result.degenerate = lm.degenerate;
    result.eigenvalues = lm.eigenvalues;
    result.information_ratio = lm.information_ratio;
    const Pose step = lm.T_world_lidar * T.inverse();
    T = lm.T_world_lidar;
    registered = true;
    result.registered = true;
    if (step.translation().norm() < config_.convergence_m &&
        Eigen::AngleAxisd(step.linear()).angle() < config_.convergence_m) {
      result.converged = true;
      break;
    }
  }
  return registered;
}

void LidarOdometry::update_map(const Features& features, const Pose& T_world_lidar) {
  if (!config_.update_map) return;
  if (config_.target == MatchTarget::kPreviousFrame) map_.clear();
  map_.insert(to_world(features.edge_candidates, T_world_lidar),
              to_world(features.plane_candidates, T_world_lidar));
  if (frames_ % 10 == 0) map_.crop(T_world_lidar.translation());
}

}  // namespace fieldlidar::odometry
