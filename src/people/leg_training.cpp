#include "fieldlidar/people/leg_training.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace fieldlidar::people {

double MatchCounts::precision() const {
  const auto d = true_positive + false_positive;
  return d ? double(true_positive) / double(d) : 1.0;
}
double MatchCounts::recall() const {
  const auto d = true_positive + false_negative;
  return d ? double(true_positive) / double(d) : 1.0;
}
MatchCounts& MatchCounts::operator+=(const MatchCounts& o) {
  true_positive += o.true_positive;
  false_positive += o.false_positive;
  false_negative += o.false_negative;
  return *this;
}

bool in_bearing_wedge(const Eigen::Vector2d& p, double bearing_min_deg, double bearing_max_deg,
                      double range_max_m) {
  const double bearing_deg = std::atan2(p.y(), p.x()) * 180.0 / M_PI;
  return p.norm() <= range_max_m && bearing_deg >= bearing_min_deg &&
         bearing_deg <= bearing_max_deg;
}

MatchCounts match_points(std::span<const Eigen::Vector2d> det,
                         std::span<const Eigen::Vector2d> truth, double radius,
                         std::vector<char>* matched) {
  struct Pair {
    double d;
    std::size_t a, b;
  };
  std::vector<Pair> pairs;
  for (std::size_t i = 0; i < det.size(); ++i)
    for (std::size_t j = 0; j < truth.size(); ++j) {
      const double d = (det[i] - truth[j]).norm();
      if (d <= radius) pairs.push_back({d, i, j});
    }
  std::sort(pairs.begin(), pairs.end(), [](const Pair& x, const Pair& y) { return x.d < y.d; });
  std::vector<bool> used_d(det.size()), used_t(truth.size());
  MatchCounts m;
  for (const auto& p : pairs) {
    if (used_d[p.a] || used_t[p.b]) continue;
    used_d[p.a] = used_t[p.b] = true;
    ++m.true_positive;
  }
  m.false_positive = det.size() - m.true_positive;
  if (matched) matched->assign(used_d.begin(), used_d.end());
  m.false_negative = truth.size() - m.true_positive;
  return m;
}

std::vector<LabelledArc> label_arcs_2d(std::span<const Eigen::Vector2d> ordered,
                                       std::span<const Eigen::Vector2d> truth,
                                       const LegDetectorConfig& config, double radius) {
  std::vector<Eigen::Vector2d> pts;
  for (const auto& p : ordered) {
    const double r = p.norm();
    if (p.allFinite() && r >= config.range_min_m && r <= config.range_max_m) pts.push_back(p);
  }
  std::vector<LabelledArc> out;
  for (const auto& [b, e] : split_by_jump(pts, config.segment_jump_m)) {
    LabelledArc a;
    a.features = arc_features(std::span(pts).subspan(b, e - b), config);
    a.foreground = in_foreground(pts, b, e, config.foreground_margin_m);
    for (const auto& t : truth)
      if ((t - a.features.midpoint_m).norm() <= radius) a.leg = true;
    out.push_back(a);
  }
  return out;
}

std::vector<double> leg_pair_distances(std::span<const Eigen::Vector2d> truth, double max_m) {
  std::vector<double> out;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t j = 0; j < truth.size(); ++j)
      if (i != j) best = std::min(best, (truth[i] - truth[j]).norm());
    if (best < max_m) out.push_back(best);
  }
  return out;
}

namespace {
double quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  const double pos = std::clamp(q, 0.0, 1.0) * double(v.size() - 1);
  const auto i = std::size_t(pos);
  const double f = pos - double(i);
  return i + 1 < v.size() ? v[i] * (1 - f) + v[i + 1] * f : v[i];
}
}  // namespace

TrainingResult estimate_leg_bounds(const std::vector<LabelledArc>& arcs,
                                   const std::vector<double>& pairs, const LegDetectorConfig& base,
                                   const TrainingOptions& o) {
  std::vector<double> curve, path, chord, points, radius, rms;
  for (const auto& a : arcs) {
    if (!a.leg) continue;
    const auto& f = a.features;
    if (!std::isfinite(f.curve)) continue;
    curve.push_back(f.curve);
    path.push_back(f.path_m);
    chord.push_back(f.chord_m);
    points.push_back(double(f.points));
    if (std::isfinite(f.circle_radius_m)) {
      radius.push_back(f.circle_radius_m);
      rms.push_back(f.circle_rms_m);
    }
  }
  if (curve.empty()) throw std::invalid_argument("estimate_leg_bounds: no leg arcs to learn from");
  TrainingResult r;
  r.leg_arcs = curve.size();
  r.other_arcs = std::size_t(
      std::count_if(arcs.begin(), arcs.end(), [](const LabelledArc& a) { return !a.leg; }));
  r.leg_pairs = pairs.size();
  LegDetectorConfig c = base;
  const double lo = 1 - o.margin, hi = 1 + o.margin;
  // Seed bounds: Curve < delta_c, L_min < L_k < L_max, dist_max.
  c.curve_max = quantile(curve, o.high_quantile) * hi;
  c.path_min_m = quantile(path, o.low_quantile) * lo;
  c.path_max_m = quantile(path, o.high_quantile) * hi;
  if (!pairs.empty()) c.pair_distance_max_m = quantile(pairs, o.high_quantile) * hi;
  // Additions.
  c.min_points = std::max(2, int(std::floor(quantile(points, o.low_quantile))));
  c.chord_max_m = quantile(chord, o.high_quantile) * hi;
  if (!radius.empty()) {
    c.radius_min_m = quantile(radius, o.low_quantile) * lo;
    c.radius_max_m = quantile(radius, o.high_quantile) * hi;
    c.circle_rms_max_m = quantile(rms, o.high_quantile) * hi;
  }
  LegDetectorConfig seed_only = c;
  seed_only.use_min_points = seed_only.use_chord_max = seed_only.use_circle_fit =
      seed_only.use_curve_min = seed_only.use_foreground = false;
  LegDetectorConfig with_additions = c;
  with_additions.use_min_points = with_additions.use_chord_max = with_additions.use_circle_fit =
      with_additions.use_curve_min = true;
  std::size_t os = 0, oa = 0, ls = 0, la = 0;
  for (const auto& a : arcs) {
    const bool s = classify_arc(a.features, seed_only) == ArcVerdict::kLeg;
    const bool all = classify_arc(a.features, with_additions) == ArcVerdict::kLeg;
    (a.leg ? ls : os) += s;
    (a.leg ? la : oa) += all;
  }
  const double n_leg = double(std::max<std::size_t>(r.leg_arcs, 1));
  const double n_other = double(std::max<std::size_t>(r.other_arcs, 1));
  r.leg_accepted_seed = double(ls) / n_leg;
  r.leg_accepted_all = double(la) / n_leg;
  r.other_accepted_seed = double(os) / n_other;
  r.other_accepted_all = double(oa) / n_other;
  r.config = c;
  return r;
}

}  // namespace fieldlidar::people
