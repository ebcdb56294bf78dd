#include "fieldlidar/people/leg_detector.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include <Eigen/Dense>

namespace fieldlidar::people {

namespace {

/// Algebraic (Kasa) circle fit: x^2 + y^2 + a x + b y + c = 0 in least squares, centred on the
/// points' mean for conditioning. Returns false when the points are (nearly) collinear.
bool fit_circle(std::span<const Eigen::Vector2d> pts, Eigen::Vector2d& center, double& radius,
                double& rms) {
  if (pts.size() < 3) return false;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& p : pts) mean += p;
  mean /= double(pts.size());
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
  for (const auto& p : pts) scatter += (p - mean) * (p - mean).transpose();
  const Eigen::Vector2d ev = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(scatter).eigenvalues();
  if (!(ev[0] > 1e-12 * ev[1])) return false;  // collinear: no finite circle
  Eigen::Matrix3d ata = Eigen::Matrix3d::Zero();
  Eigen::Vector3d atb = Eigen::Vector3d::Zero();
  for (const auto& p0 : pts) {
    const Eigen::Vector2d p = p0 - mean;
    const Eigen::Vector3d row(p.x(), p.y(), 1.0);
    ata += row * row.transpose();
    atb += row * (-p.squaredNorm());
  }
  const Eigen::Vector3d sol = ata.ldlt().solve(atb);
  if (!sol.allFinite()) return false;
  const Eigen::Vector2d c(-sol.x() / 2, -sol.y() / 2);
  const double r2 = c.squaredNorm() - sol.z();
  if (!(r2 > 0) || !std::isfinite(r2)) return false;
  radius = std::sqrt(r2);
  center = c + mean;
  double sum = 0;
  for (const auto& p : pts) {
    const double d = (p - center).norm() - radius;
    sum += d * d;
  }
  rms = std::sqrt(sum / double(pts.size()));
  return true;
}

}  // namespace

LegDetectorConfig default_2d_legs() {
  // `fieldlidar legs-train` on the four annotated positive_*_extracted bags and negative_2.bag
  // of ../shared/data/legs_2d, quantiles 0.02 / 0.98 (config/legs_2d.yaml).
  LegDetectorConfig c;
  c.min_rings = 1;
  c.curve_max = 1.722;
  c.path_min_m = 0.052;
  c.path_max_m = 0.544;
  c.pair_distance_max_m = 0.463;
  c.use_min_points = true;
  c.min_points = 4;
  c.use_chord_max = true;
  c.chord_max_m = 0.395;
  c.use_circle_fit = true;
  c.radius_min_m = 0.030;
  c.radius_max_m = 0.518;
  c.circle_rms_max_m = 0.042;
  c.use_curve_min = true;
  c.use_background = true;
  return c;
}

LegDetectorConfig seed_only(LegDetectorConfig c) {
  c.use_min_points = c.use_chord_max = c.use_circle_fit = c.use_curve_min = false;
  c.use_foreground = c.use_background = false;
  c.smooth_window = 1;
  c.path_step_m = 0.0;
  c.classifier.reset();
  return c;
}

ArcFeatures compute_arc_features(std::span<const Eigen::Vector2d> pts, double path_step_m) {
  ArcFeatures f;
  f.points = pts.size();
  if (pts.empty()) return f;
  // seed 000, step 3, formula 1): path length over consecutive points and chord first-to-last
  if (path_step_m > 0) {
    Eigen::Vector2d last = pts.front();
    for (std::size_t j = 1; j < pts.size(); ++j) {
      const double d = (pts[j] - last).norm();
      if (d >= path_step_m || j + 1 == pts.size()) {
        f.path_m += d;
        last = pts[j];
      }
    }
  } else {
    for (std::size_t j = 0; j + 1 < pts.size(); ++j) f.path_m += (pts[j + 1] - pts[j]).norm();
  }
  f.chord_m = (pts.back() - pts.front()).norm();
  // formula 2): the bend
  f.curve = f.chord_m > 0 ? f.path_m / f.chord_m : std::numeric_limits<double>::infinity();
  for (const auto& p : pts) f.midpoint_m += p;
  f.midpoint_m /= double(pts.size());
  if (!fit_circle(pts, f.circle_center_m, f.circle_radius_m, f.circle_rms_m)) {
    f.circle_radius_m = std::numeric_limits<double>::infinity();
    f.circle_rms_m = std::numeric_limits<double>::infinity();
  }
  return f;
}

std::vector<Eigen::Vector2d> smooth_arc(std::span<const Eigen::Vector2d> pts, int window) {
  std::vector<Eigen::Vector2d> out(pts.begin(), pts.end());
  const int half = std::max(window, 1) / 2;
  if (half == 0) return out;
  const int n = int(pts.size());
  for (int j = 0; j < n; ++j) {
    const int h = std::min({half, j, n - 1 - j});  // symmetric window keeps the end points
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    for (int k = j - h; k <= j + h; ++k) sum += pts[std::size_t(k)];
    out[std::size_t(j)] = sum / double(2 * h + 1);
  }
  return out;
}

ArcFeatures arc_features(std::span<const Eigen::Vector2d> pts, const LegDetectorConfig& c) {
  if (c.smooth_window <= 1) return compute_arc_features(pts, c.path_step_m);
  const auto smooth = smooth_arc(pts, c.smooth_window);
  auto f = compute_arc_features(smooth, c.path_step_m);
  // Position and circle from the measured points, not the smoothed ones.
  const auto raw = compute_arc_features(pts, 0.0);
  f.midpoint_m = raw.midpoint_m;
  f.circle_center_m = raw.circle_center_m;
  f.circle_radius_m = raw.circle_radius_m;
  f.circle_rms_m = raw.circle_rms_m;
  return f;
}

std::vector<std::pair<std::size_t, std::size_t>> split_by_jump(std::span<const Eigen::Vector2d> pts,
                                                               double jump_m) {
  std::vector<std::pair<std::size_t, std::size_t>> out;
  std::size_t begin = 0;
  for (std::size_t j = 1; j <= pts.size(); ++j) {
    if (j == pts.size() || (pts[j] - pts[j - 1]).norm() > jump_m) {
      if (j > begin) out.emplace_back(begin, j);
      begin = j;
    }
  }
  return out;
}

ArcVerdict classify_arc(const ArcFeatures& arc, const LegDetectorConfig& c) {
  if (c.use_min_points && arc.points < std::size_t(std::max(c.min_points, 0)))
    return ArcVerdict::kTooFewPoints;
  // seed 000, step 3, formula 3): Curve < delta_c and L_min < L_k < L_max
  if (!(arc.curve < c.curve_max)) return ArcVerdict::kCurve;
  if (!(arc.path_m > c.path_min_m && arc.path_m < c.path_max_m)) return ArcVerdict::kPathLength;
  if (c.use_chord_max && arc.chord_m > c.chord_max_m) return ArcVerdict::kChord;
  if (c.use_curve_min && arc.curve <= c.curve_min) return ArcVerdict::kStraight;
  if (c.use_circle_fit &&
      !(arc.circle_radius_m >= c.radius_min_m && arc.circle_radius_m <= c.radius_max_m &&
        arc.circle_rms_m <= c.circle_rms_max_m))
    return ArcVerdict::kCircle;
  return ArcVerdict::kLeg;
}

bool in_foreground(std::span<const Eigen::Vector2d> pts, std::size_t begin, std::size_t end,
                   double margin_m) {
  double nearest = std::numeric_limits<double>::infinity();
  for (std::size_t j = begin; j < end; ++j) nearest = std::min(nearest, pts[j].norm());
  if (begin > 0 && pts[begin - 1].norm() < nearest - margin_m) return false;
  if (end < pts.size() && pts[end].norm() < nearest - margin_m) return false;
  return true;
}

std::vector<Eigen::Vector2d> scan_points_2d(const PointCloud& scan, bool upside_down) {
  std::vector<Eigen::Vector2d> pts;
  pts.reserve(scan.size());
  for (const auto& p : scan.points)
    if (p.is_valid()) pts.emplace_back(p.x, upside_down ? -p.y : p.y);
  if (upside_down) std::reverse(pts.begin(), pts.end());
  return pts;
}

std::vector<Eigen::Vector2d> points_in_range(std::span<const Eigen::Vector2d> ordered_points,
                                             const LegDetectorConfig& config) {
  std::vector<Eigen::Vector2d> pts;
  pts.reserve(ordered_points.size());
  for (const auto& p : ordered_points) {
    const double r = p.norm();
    if (p.allFinite() && r >= config.range_min_m && r <= config.range_max_m) pts.push_back(p);
  }
  return pts;
}

LegDetection detect_legs_2d(std::span<const Eigen::Vector2d> ordered_points,
                            const LegDetectorConfig& config, const StaticBackground* background) {
  LegDetection out;
  const std::vector<Eigen::Vector2d> pts = points_in_range(ordered_points, config);
  const auto segments = split_by_jump(pts, config.segment_jump_m);
  for (std::size_t s = 0; s < segments.size(); ++s) {
    const auto [b, e] = segments[s];
    const auto arc = arc_features(std::span(pts).subspan(b, e - b), config);
    ++out.arcs_tested;
    if (config.classifier) {
      if (!config.classifier->is_leg(segment_features(pts, b, e))) continue;
    } else if (classify_arc(arc, config) != ArcVerdict::kLeg) {
      continue;
    }
    if (config.use_foreground && !in_foreground(pts, b, e, config.foreground_margin_m)) continue;
    if (config.use_background && background &&
        background->is_static(std::span(pts).subspan(b, e - b)))
      continue;
    out.legs.push_back({arc.midpoint_m, 1, std::int32_t(s)});
  }
  pair_legs(out, config);
  return out;
}

std::vector<RingArc> extract_ring_arcs(const PointCloud& cloud,
                                       std::span<const std::vector<std::uint32_t>> clusters,
                                       const LegDetectorConfig& config) {
  std::vector<RingArc> arcs;
  std::vector<std::pair<double, std::uint32_t>> by_azimuth;
  std::vector<Eigen::Vector2d> ring_pts;
  std::vector<std::pair<std::size_t, std::size_t>> pieces;
  for (std::size_t k = 0; k < clusters.size(); ++k) {
    const auto& idx = clusters[k];
    if (idx.empty()) continue;
    Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
    for (auto i : idx) centroid += Eigen::Vector2d(cloud.points[i].x, cloud.points[i].y);
    centroid /= double(idx.size());
    const double range = centroid.norm();
    if (range < config.range_min_m || range > config.range_max_m) continue;  // range S
    // Azimuth relative to the centroid's direction, so that clusters across +-pi sort correctly.
    const double az0 = std::atan2(centroid.y(), centroid.x());
    by_azimuth.clear();
    for (auto i : idx) {
      const auto& p = cloud.points[i];
      by_azimuth.emplace_back(std::remainder(std::atan2(double(p.y), double(p.x)) - az0, 2 * M_PI),
                              i);
    }
    // Group by ring, then azimuth order within the ring.
    std::sort(by_azimuth.begin(), by_azimuth.end(), [&](const auto& a, const auto& b) {
      const auto ra = cloud.points[a.second].ring, rb = cloud.points[b.second].ring;
      return ra != rb ? ra < rb : a.first < b.first;
    });
    for (std::size_t s = 0; s < by_azimuth.size();) {
      const auto ring = cloud.points[by_azimuth[s].second].ring;
      std::size_t e = s;
      ring_pts.clear();
      pieces.clear();
      std::size_t piece_begin = 0;
      while (e < by_azimuth.size() && cloud.points[by_azimuth[e].second].ring == ring) {
        const auto& p = cloud.points[by_azimuth[e].second];
        ring_pts.emplace_back(p.x, p.y);  // projection onto the ring's plane
        if (e > s && config.split_azimuth_gap_rad > 0 &&
            by_azimuth[e].first - by_azimuth[e - 1].first > config.split_azimuth_gap_rad) {
          pieces.emplace_back(piece_begin, ring_pts.size() - 1);
          piece_begin = ring_pts.size() - 1;
        }
        ++e;
      }
      pieces.emplace_back(piece_begin, ring_pts.size());
      for (const auto& [pb, pe] : pieces)
        for (const auto& [b, en] :
             split_by_jump(std::span(ring_pts).subspan(pb, pe - pb), config.segment_jump_m)) {
          RingArc arc;
          arc.cluster = std::int32_t(k);
          arc.ring = ring;
          for (std::size_t j = pb + b; j < pb + en; ++j)
            arc.indices.push_back(by_azimuth[s + j].second);
          arc.features = arc_features(std::span(ring_pts).subspan(pb + b, en - b), config);
          arcs.push_back(std::move(arc));
        }
      s = e;
    }
  }
  return arcs;
}

LegDetection detect_legs_3d(const PointCloud& cloud,
                            std::span<const std::vector<std::uint32_t>> clusters,
                            const LegDetectorConfig& config) {
  LegDetection out;
  struct Group {
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    int arcs = 0;
    std::int32_t cluster = -1;
    std::vector<std::uint16_t> rings;
    Eigen::Vector2d mean() const { return sum / double(arcs); }
  };
  std::vector<Group> groups;
  const auto arcs = extract_ring_arcs(cloud, clusters, config);
  out.arcs_tested = arcs.size();
  for (const auto& arc : arcs) {
    if (classify_arc(arc.features, config) != ArcVerdict::kLeg) continue;
    // Leg arcs of one cluster on different rings within the merge radius are one leg.
    Group* best = nullptr;
    double best_d = config.leg_merge_radius_m;
    for (auto& g : groups) {
      const double d = (g.mean() - arc.features.midpoint_m).norm();
      if (g.cluster == arc.cluster && d <= best_d &&
          std::find(g.rings.begin(), g.rings.end(), arc.ring) == g.rings.end()) {
        best = &g;
        best_d = d;
      }
    }
    if (!best) {
      groups.emplace_back();
      best = &groups.back();
      best->cluster = arc.cluster;
    }
    best->sum += arc.features.midpoint_m;
    ++best->arcs;
    best->rings.push_back(arc.ring);
  }
  for (const auto& g : groups)
    if (g.arcs >= std::max(config.min_rings, 1)) out.legs.push_back({g.mean(), g.arcs, g.cluster});
  pair_legs(out, config);
  return out;
}

void pair_legs(LegDetection& detection, const LegDetectorConfig& config) {
  detection.people.clear();
  const auto& legs = detection.legs;
  struct Candidate {
    double d;
    std::size_t a, b;
  };
  std::vector<Candidate> candidates;
  for (std::size_t a = 0; a < legs.size(); ++a)
    for (std::size_t b = a + 1; b < legs.size(); ++b) {
      const double d = (legs[a].position_m - legs[b].position_m).norm();
      if (d < config.pair_distance_max_m) candidates.push_back({d, a, b});
    }
  std::sort(candidates.begin(), candidates.end(),
            [](const Candidate& x, const Candidate& y) { return x.d < y.d; });
  std::vector<bool> used(legs.size(), false);
  for (const auto& c : candidates) {
    if (used[c.a] || used[c.b]) continue;
    used[c.a] = used[c.b] = true;
    detection.people.push_back({0.5 * (legs[c.a].position_m + legs[c.b].position_m), {c.a, c.b}});
  }
}

}  // namespace fieldlidar::people
