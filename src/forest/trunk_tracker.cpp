// Pose tracking against a trunk map: predict (constant velocity or a given prior), de-skew,
// extract the trees, associate them with the mapped trunks near the prediction, solve the pose
// from the axes and the ground plane, and merge the observations into the map.
#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <unordered_map>

#include <Eigen/Geometry>

#include "fieldlidar/core/pose.hpp"
#include "fieldlidar/forest/tracking.hpp"

namespace fieldlidar::forest {
namespace {

// Every point moved into the frame of the sweep start, under a constant motion over the sweep:
// a point fired at time t moves by the fraction t / period of the motion (rotation angle and
// translation scaled). The motion's axis and angle are taken once; the fraction's rotation once
// per firing time (the points of one firing share it, and a ring-major cloud repeats the times of
// the first ring).
PointCloud deskewed(const PointCloud& cloud, const Pose& motion, double period_s) {
  PointCloud out = cloud;
  const Eigen::AngleAxisd aa(motion.linear());
  struct Fraction {
    Eigen::Matrix3d R;
    Eigen::Vector3d t;
  };
  std::unordered_map<std::uint32_t, Fraction> by_time;  // by the time's bits
  float last_time = std::numeric_limits<float>::quiet_NaN();
  const Fraction* f = nullptr;
  for (auto& p : out.points) {
    if (!p.is_valid()) continue;
    if (!(p.time == last_time)) {
      last_time = p.time;
      auto [it, added] = by_time.try_emplace(std::bit_cast<std::uint32_t>(p.time));
      if (added) {
        const double s = double(p.time) / period_s;
        it->second.R = Eigen::AngleAxisd(aa.angle() * s, aa.axis()).toRotationMatrix();
        it->second.t = motion.translation() * s;
      }
      f = &it->second;
    }
    const Eigen::Vector3d q = f->R * p.xyz().cast<double>() + f->t;
    p.x = float(q.x());
    p.y = float(q.y());
    p.z = float(q.z());
  }
  return out;
}

// Weight of one observation: near, well-covered stems count more.
double weight_of(const Tree& t) {
  const double range = t.at_height(1.3).head<2>().norm();
  return std::clamp(t.arc_deg / 180.0, 0.2, 1.0) / (1.0 + 0.01 * range * range);
}

}  // namespace

TrunkTracker::TrunkTracker(const TrackerConfig& config) : config_(config) {}

TrackResult TrunkTracker::track(const PointCloud& cloud, std::span<const std::uint8_t> is_ground,
                                const std::optional<Pose>& prior_motion) {
  TrackResult res;
  const Pose motion = prior_motion ? *prior_motion : smooth_motion_;
  const Pose predicted = started_ ? T_world_lidar_ * motion : Pose::Identity();
  const bool skew = config_.deskew && cloud.fields.time && started_;
  const PointCloud straight = skew ? deskewed(cloud, motion, config_.sweep_period_s) : PointCloud{};
  const PointCloud& scan = skew ? straight : cloud;
  std::vector<Tree> trees = extract_trees(scan, is_ground, config_.trees).trees;
  std::erase_if(trees, [&](const Tree& t) {
    return t.at_height(1.3).head<2>().norm() > config_.max_range_m;
  });
  res.trees = trees.size();
  const auto current = landmarks_of(trees);
  const GroundPlane ground = fit_ground_plane(scan, is_ground);
  Pose T = predicted;
  std::vector<std::pair<std::size_t, std::size_t>> matches;
  std::vector<std::size_t> map_index;
  if (started_) {
    std::vector<TrunkLandmark> near;
    for (std::size_t k = 0; k < map_.size(); ++k)
      if ((map_[k].landmark.point - predicted.translation()).head<2>().norm() <=
          config_.map_radius_m) {
        near.push_back(map_[k].landmark);
        map_index.push_back(k);
      }
    matches = associate_trunks(near, current, predicted, config_.association);
    GroundPlane cur_ground = ground;
    if (matches.size() >= config_.association.min_matches || (ground.ok && world_ground_.ok)) {
      if (matches.size() < config_.association.min_matches) matches.clear();
      T = estimate_trunk_motion(near, current, matches, world_ground_, cur_ground, predicted,
                                config_.motion);
      res.tracked = matches.size() >= config_.association.min_matches;
    }
    res.matched = matches.size();
    for (auto& m : matches) m.first = map_index[m.first];
  }
  if (!T.matrix().allFinite()) T = predicted;
  last_motion_ = started_ ? T_world_lidar_.inverse() * T : Pose::Identity();
  // The prediction and de-skew take a smoothed motion: a single frame's error would otherwise
  // come back through the de-skew of the next one.
  if (started_) {
    const double a = config_.motion_smoothing;
    const Eigen::AngleAxisd r_new(last_motion_.linear()), r_old(smooth_motion_.linear());
    const Eigen::Vector3d w =
        a * r_new.angle() * r_new.axis() + (1 - a) * r_old.angle() * r_old.axis();
    smooth_motion_.linear() = exp_so3(w);
    smooth_motion_.translation() =
        a * last_motion_.translation() + (1 - a) * smooth_motion_.translation();
  }
  T_world_lidar_ = T;
  if (ground.ok) {
    const Eigen::Vector3d n = T.linear() * ground.normal;
    world_ground_ = {n, ground.offset - n.dot(T.translation()), true};
  } else {
    world_ground_.ok = false;
  }
  update_map(trees, current, matches, {});
  started_ = true;
  res.T_world_lidar = T;
  return res;
}

void TrunkTracker::update_map(std::span<const Tree> trees, std::span<const TrunkLandmark> current,
                              std::span<const std::pair<std::size_t, std::size_t>> matches,
                              std::span<const std::size_t>) {
  const Pose& T = T_world_lidar_;
  std::vector<char> used(current.size(), 0);
  auto add = [&](MappedTrunk& m, std::size_t j) {
    const double w = weight_of(trees[j]);
    m.weight += w;
    const double w_dbh = trees[j].dbh_uncertain ? 1e-3 * w : w;
    m.dbh_weight += w_dbh;
    m.dbh_weighted_sum += w_dbh * current[j].dbh_m;
    m.point_weighted_sum += w * (T * current[j].point);
    m.landmark.point = m.point_weighted_sum / m.weight;
    m.landmark.dbh_m = m.dbh_weighted_sum / m.dbh_weight;
    const Eigen::Vector3d a = T.linear() * current[j].axis;
    m.landmark.axis = (m.landmark.axis * (m.weight - w) + a * w).normalized();
    m.base_z_m = (m.base_z_m * (m.weight - w) + (T * trees[j].base_m).z() * w) / m.weight;
    m.height_seen_m = std::max(m.height_seen_m, trees[j].z_max_seen_m - trees[j].z_min_seen_m);
    m.arc_deg = std::max(m.arc_deg, trees[j].arc_deg);
    m.residual_m =
        (m.residual_m * double(m.observations) + trees[j].residual_m) / double(m.observations + 1);
    ++m.observations;
  };
  for (const auto& [k, j] : matches) {
    add(map_[k], j);
    used[j] = 1;
  }
  for (std::size_t j = 0; j < current.size(); ++j) {
    if (used[j]) continue;
    const Eigen::Vector3d p = T * current[j].point;
    bool near = false;
    for (auto& m : map_) {
      const double d = (m.landmark.point - p).head<2>().norm();
      if (d >= config_.new_trunk_distance_m) continue;
      near = true;
      // A mapped 'trunk' on the surface of this thicker stem, too thin to be matched with it,
      // was a branch of it: the stem takes its place once seen there in as many scans as a map
      // trunk needs to be reported.
      const double tol = config_.association.dbh_tolerance_m + 0.3 * current[j].dbh_m;
      if (current[j].dbh_m - m.landmark.dbh_m > tol && d < current[j].dbh_m / 2 + 0.1 &&
          ++m.thicker_seen >= config_.map_min_observations) {
        const std::uint32_t id = m.id;
        m = MappedTrunk{};
        m.id = id;
        m.landmark = {p, T.linear() * current[j].axis, current[j].dbh_m};
        add(m, j);
      }
      break;
    }
    if (near) continue;
    MappedTrunk m;
    m.id = std::uint32_t(map_.size() + 1);
    m.landmark = {p, T.linear() * current[j].axis, current[j].dbh_m};
    add(m, j);
    map_.push_back(m);
  }
}

std::vector<Tree> TrunkTracker::map_trees() const {
  std::vector<Tree> out;
  for (const auto& m : map_) {
    if (m.observations < config_.map_min_observations) continue;
    Tree t;
    t.id = m.id;
    t.axis = m.landmark.axis;
    const double h = m.landmark.point.z() - m.base_z_m;
    t.base_m = m.landmark.point - t.axis * (h / t.axis.z());
    t.dbh_m = m.landmark.dbh_m;
    t.z_min_seen_m = 0.0;
    t.z_max_seen_m = m.height_seen_m;
    t.arc_deg = m.arc_deg;
    t.residual_m = m.residual_m;
    t.observations = m.observations;
    t.ground_found = true;
    t.dbh_uncertain = m.dbh_weight < 0.01 * m.weight;  // no observation measured it
    out.push_back(t);
  }
  return out;
}

}  // namespace fieldlidar::forest
