#pragma once
// Detection and DBH scores of forest::extract_trees on simulated forest frames.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <vector>

#include "fieldlidar/core/labels.hpp"
#include "fieldlidar/forest/trunks.hpp"
#include "fieldlidar/segmentation/ground.hpp"
#include "fieldlidar/sim/lidar_simulator.hpp"
#include "fieldlidar/sim/motion.hpp"
#include "fieldlidar/sim/scenes.hpp"

namespace fieldlidar::forest::test {

/// DBH figures leave out the detections marked dbh_uncertain (counted in `uncertain`, their
/// guess's error in dbh_all_rmse(); `fieldlidar trunks` leaves their dbh_m empty), so
/// dbh_rmse() is over every diameter the inventory gives; detection and position figures take
/// every detection.
struct Scores {
  int truth = 0, detected = 0, matched = 0, uncertain = 0;
  double dbh_sq = 0, dbh_sum = 0, pos_sq = 0, dbh_sq_uncertain = 0;
  double recall() const { return truth ? double(matched) / truth : 1.0; }
  double precision() const { return detected ? double(matched) / detected : 1.0; }
  int dbh_scored() const { return matched - uncertain; }
  double dbh_rmse() const { return dbh_scored() ? std::sqrt(dbh_sq / dbh_scored()) : 0.0; }
  double dbh_bias() const { return dbh_scored() ? dbh_sum / dbh_scored() : 0.0; }
  double dbh_all_rmse() const {
    return matched ? std::sqrt((dbh_sq + dbh_sq_uncertain) / matched) : 0.0;
  }
  void add(const Scores& o) {
    truth += o.truth;
    detected += o.detected;
    matched += o.matched;
    uncertain += o.uncertain;
    dbh_sq += o.dbh_sq;
    dbh_sum += o.dbh_sum;
    pos_sq += o.pos_sq;
    dbh_sq_uncertain += o.dbh_sq_uncertain;
  }
  double pos_rmse() const { return matched ? std::sqrt(pos_sq / matched) : 0.0; }
  void print(const char* name) const {
    std::printf(
        "%s: truth %d detected %d matched %d recall %.3f precision %.3f DBH RMSE %.4f m "
        "bias %+.4f m position RMSE %.4f m; DBH uncertain %d (RMSE with them %.4f m)\n",
        name, truth, detected, matched, recall(), precision(), dbh_rmse(), dbh_bias(), pos_rmse(),
        uncertain, dbh_all_rmse());
  }
};

/// Which true trees are scored. A tree is scored when its stem at 1.3 m lies within `range_m` of
/// the sensor, the frame holds at least `min_hits` returns labelled with it, and at least
/// `min_visible` of its outline at 1.3 m is seen from the sensor (visible_fraction: rays cast in
/// the truth scene across the stem's silhouette, every other stem, branch and shrub in the way).
/// 0.5 asks for the near side on the axis bearing: less is a sliver beside an occluder, whose
/// diameter no single view holds. 0: the returns alone decide (the rule before).
struct ScoreRule {
  double range_m = 15.0;
  double match_m = 0.3;
  int min_hits = 20;
  double min_visible = 0.5;
};

/// Share of tree `t`'s outline at 1.3 m above its base (a circle of its DBH) that the sensor at
/// `sensor` sees: `rays` rays evenly across the silhouette's angle, each counted when the
/// first thing it hits is this stem.
inline double visible_fraction(const sim::LidarSimulator& simulator, const sim::TreeTruth& t,
                               const Eigen::Vector3d& sensor, int rays = 48) {
  const Eigen::Vector3d p = t.base_m + t.axis * (1.3 / t.axis.z());
  const Eigen::Vector2d d = (p - sensor).head<2>();
  const double dist = d.norm(), r = t.dbh_m / 2;
  if (dist <= r) return 1.0;
  const double half = std::asin(r / dist), bearing = std::atan2(d.y(), d.x());
  int seen = 0;
  for (int k = 0; k < rays; ++k) {
    const double az = bearing + half * (2.0 * (k + 0.5) / rays - 1.0);
    const Eigen::Vector3d dir =
        Eigen::Vector3d(std::cos(az), std::sin(az), (p.z() - sensor.z()) / dist).normalized();
    const auto hit = simulator.cast(sensor, dir, dist + r + 1.0);
    seen +=
        hit && label_class(hit->label) == LabelClass::kTrunk && label_instance(hit->label) == t.id;
  }
  return double(seen) / rays;
}

/// A detection matches the nearest unmatched scored tree within `match_m` at 1.3 m; detections
/// beyond range_m + 1 m are not scored; one matching an unscored (occluded) tree is neither right
/// nor wrong. `simulator` may be null only when rule.min_visible is 0.
inline void score_frame(const sim::Scene& scene, const sim::SimFrame& frame,
                        const std::vector<Tree>& trees, Scores& s,
                        const sim::LidarSimulator* simulator, const ScoreRule& rule = {}) {
  const double range_m = rule.range_m, match_m = rule.match_m;
  std::map<std::uint16_t, int> hits;
  for (auto l : frame.cloud.labels)
    if (label_class(l) == LabelClass::kTrunk) ++hits[label_instance(l)];
  const Pose T = frame.T_world_lidar_start;
  const Eigen::Vector3d sensor = T.translation();
  struct Truth {
    Eigen::Vector2d xy;
    double dbh;
    bool scored;
    bool used = false;
    int hits = 0;
    double range = 0;
    double visible = 1.0;
  };
  std::vector<Truth> truth;
  for (const auto& t : scene.trunks()) {
    const Eigen::Vector3d p = t.base_m + t.axis * (1.3 / t.axis.z());
    const bool near = (p - sensor).head<2>().norm() <= range_m;
    if ((p - sensor).head<2>().norm() > range_m + 2.0) continue;
    const double visible =
        near && rule.min_visible > 0 ? visible_fraction(*simulator, t, sensor) : 1.0;
    truth.push_back({p.head<2>(), t.dbh_m,
                     near && hits[t.id] >= rule.min_hits && visible >= rule.min_visible, false,
                     hits[t.id], (p - sensor).head<2>().norm(), visible});
    s.truth += truth.back().scored;
  }
  for (const auto& d : trees) {
    const Eigen::Vector3d p = T * d.at_height(1.3);
    if ((p - sensor).head<2>().norm() > range_m + 1.0) continue;
    Truth* best = nullptr;
    double best_d = match_m;
    for (auto& t : truth)
      if (!t.used && (t.xy - p.head<2>()).norm() < best_d) {
        best_d = (t.xy - p.head<2>()).norm();
        best = &t;
      }
    if (best && !best->scored) {
      best->used = true;
      continue;
    }
    ++s.detected;
    if (!best) continue;
    best->used = true;
    ++s.matched;
    const double e = d.dbh_m - best->dbh;
    if (d.dbh_uncertain) {
      ++s.uncertain;
      s.dbh_sq_uncertain += e * e;
    } else {
      s.dbh_sq += e * e;
      s.dbh_sum += e;
    }
    s.pos_sq += best_d * best_d;
    if (std::getenv("FOREST_DEBUG"))
      std::printf(
          "    dbh %.3f true %.3f arc %.0f res %.4f obs %zu range %.1f visible %.2f at %.2f "
          "%.2f seen %.2f-%.2f%s\n",
          d.dbh_m, best->dbh, d.arc_deg, d.residual_m, d.observations,
          (p - sensor).head<2>().norm(), best->visible, best->xy.x(), best->xy.y(), d.z_min_seen_m,
          d.z_max_seen_m, d.dbh_uncertain ? " uncertain" : "");
  }
  if (std::getenv("FOREST_DEBUG")) {
    for (const auto& t : truth)
      if (t.scored && !t.used) {
        const Eigen::Vector3d q = T.inverse() * Eigen::Vector3d(t.xy.x(), t.xy.y(), sensor.z());
        std::printf(
            "    MISS dbh %.3f hits %d range %.1f visible %.2f at %.2f %.2f (sensor frame %.2f "
            "%.2f)\n",
            t.dbh, t.hits, t.range, t.visible, t.xy.x(), t.xy.y(), q.x(), q.y());
      }
    for (const auto& d : trees) {
      const Eigen::Vector3d p = T * d.at_height(1.3);
      bool m = false;
      for (const auto& t : truth) m |= (t.xy - p.head<2>()).norm() < match_m;
      if (!m && (p - sensor).head<2>().norm() <= range_m + 1.0)
        std::printf("    FALSE dbh %.3f arc %.0f res %.4f obs %zu range %.1f seen %.2f-%.2f\n",
                    d.dbh_m, d.arc_deg, d.residual_m, d.observations, (p - sensor).head<2>().norm(),
                    d.z_min_seen_m, d.z_max_seen_m);
      if (!m && (p - sensor).head<2>().norm() <= range_m + 1.0)
        std::printf("      at %.2f %.2f axis %.3f %.3f\n", p.x(), p.y(), d.axis.x(), d.axis.y());
    }
  }
}

/// `frames` static scans along the scene's route of forest `seed` (every 3 s of a 0.8 m/s drive).
inline Scores run_frames(std::uint64_t seed, const SensorModel& sensor, int frames,
                         const TreeConfig& config = {}, bool verbose = false,
                         const ScoreRule& rule = {}) {
  const sim::Scene scene = sim::make_forest_scene({}, seed);
  const auto motion = sim::drive_scene_route(scene, 3.0 * frames + 1.0);
  const sim::LidarSimulator simulator(scene, sensor);
  Scores s;
  for (int f = 0; f < frames; ++f) {
    const double t = 3.0 * f;
    const auto frame = simulator.scan(t, motion.lidar_pose_fn()(t));
    const auto ground = segmentation::segment_ground(frame.cloud, sensor);
    const auto result = extract_trees(frame.cloud, ground.is_ground, config);
    Scores one;
    if (std::getenv("FOREST_DEBUG")) std::printf("  frame %d\n", f);
    score_frame(scene, frame, result.trees, one, &simulator, rule);
    if (verbose) one.print("  frame");
    s.add(one);
  }
  return s;
}

}  // namespace fieldlidar::forest::test
