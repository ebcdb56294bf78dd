#include "fieldlidar/people/leg_classifier.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <ostream>
#include <sstream>
#include <stdexcept>

#include <yaml-cpp/yaml.h>
#include <Eigen/Dense>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/people/leg_detector.hpp"

namespace fieldlidar::people {

namespace {

constexpr std::array<const char*, kSegmentFeatures> kNames = {"points",
                                                              "chord_m",
                                                              "path_m",
                                                              "bend",
                                                              "circle_radius_m",
                                                              "circle_rms_m",
                                                              "linearity_m",
                                                              "std_dev_m",
                                                              "spacing_m",
                                                              "range_m",
                                                              "angular_width_rad",
                                                              "sagitta_m",
                                                              "center_behind_m",
                                                              "prev_range_diff_m",
                                                              "next_range_diff_m",
                                                              "prev_gap_m",
                                                              "next_gap_m"};

double clamp_finite(double v, double lo, double hi) {
  if (std::isnan(v)) return hi;
  return std::clamp(v, lo, hi);
}

}  // namespace

std::span<const char* const> segment_feature_names() {
  return kNames;
}

SegmentFeatures segment_features(std::span<const Eigen::Vector2d> scan, std::size_t begin,
                                 std::size_t end) {
  SegmentFeatures f{};
  const auto pts = scan.subspan(begin, end - begin);
  const auto arc = compute_arc_features(pts);
  const double n = double(pts.size());
  f[0] = n;
  f[1] = arc.chord_m;
  f[2] = arc.path_m;
  f[3] = clamp_finite(arc.curve, 1.0, 20.0);
  f[4] = clamp_finite(arc.circle_radius_m, 0.0, 5.0);
  f[5] = clamp_finite(arc.circle_rms_m, 0.0, 1.0);
  const Eigen::Vector2d mean = arc.midpoint_m;
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
  for (const auto& p : pts) scatter += (p - mean) * (p - mean).transpose();
  scatter /= std::max(n, 1.0);
  const Eigen::Vector2d ev = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(scatter).eigenvalues();
  f[6] = std::sqrt(std::max(ev[0], 0.0));            // rms distance to the principal line (m)
  f[7] = std::sqrt(std::max(scatter.trace(), 0.0));  // std dev about the centroid (m)
  f[8] = n > 1 ? arc.path_m / (n - 1) : 0.0;
  const double range = mean.norm();
  f[9] = range;
  f[10] = range > 0 ? arc.chord_m / range : 0.0;
  // Signed sagitta: distance of the points from the chord line, positive toward the sensor; a
  // leg's front bulges toward the sensor, a corner of furniture or a wall recess does not.
  double sag = 0;
  const Eigen::Vector2d a = pts.front(), b = pts.back();
  const Eigen::Vector2d chord = b - a;
  if (chord.norm() > 1e-9) {
    Eigen::Vector2d normal(-chord.y(), chord.x());
    normal.normalize();
    if (normal.dot(-a) < 0) normal = -normal;  // toward the sensor
    for (const auto& p : pts) {
      const double d = (p - a).dot(normal);
      if (std::abs(d) > std::abs(sag)) sag = d;
    }
  }
  f[11] = sag;
  f[12] = std::isfinite(arc.circle_radius_m)
              ? clamp_finite(arc.circle_center_m.norm() - range, -5.0, 5.0)
              : 5.0;
  const double near = [&] {
    double m = std::numeric_limits<double>::infinity();
    for (const auto& p : pts) m = std::min(m, p.norm());
    return m;
  }();
  f[13] = begin > 0 ? clamp_finite(scan[begin - 1].norm() - near, -5.0, 5.0) : 5.0;
  f[14] = end < scan.size() ? clamp_finite(scan[end].norm() - near, -5.0, 5.0) : 5.0;
  f[15] = begin > 0 ? std::min((scan[begin] - scan[begin - 1]).norm(), 5.0) : 5.0;
  f[16] = end < scan.size() ? std::min((scan[end] - scan[end - 1]).norm(), 5.0) : 5.0;
  return f;
}

double LegClassifier::score(const SegmentFeatures& f) const {
  double s = 0;
  for (const auto& t : trees) s += t.eval(f);
  return s;
}

namespace {

/// Binned training data: bin[k][i] is the bin of sample i in feature k; bin b holds the values in
/// (cuts[k][b-1], cuts[k][b]].
struct Binned {
  std::vector<std::vector<double>> cuts;
  std::vector<std::vector<std::uint8_t>> bin;
};

struct Split {
  Stump stump;
  double z = std::numeric_limits<double>::infinity();
};

/// Real AdaBoost's best stump over the samples with `in[i]` set: the split minimising
/// Z = 2 (sqrt(W+ W-) below + sqrt(W+ W-) above), outputs 1/2 ln(W+ / W-) per side.
Split best_split(const Binned& d, std::span<const char> y, const std::vector<double>& w,
                 const std::vector<char>& in, double eps) {
  const std::size_t n = y.size();
  double tp = 0, tn = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (in[i]) (y[i] ? tp : tn) += w[i];
  Split best;
  std::vector<double> hp, hn;
  for (std::size_t k = 0; k < d.cuts.size(); ++k) {
    const auto nb = d.cuts[k].size() + 1;
    hp.assign(nb, 0.0);
    hn.assign(nb, 0.0);
    for (std::size_t i = 0; i < n; ++i)
      if (in[i]) (y[i] ? hp : hn)[d.bin[k][i]] += w[i];
    double lp = 0, ln = 0;
    for (std::size_t b = 0; b + 1 < nb; ++b) {
      lp += hp[b];
      ln += hn[b];
      const double z =
          std::sqrt(lp * ln) + std::sqrt(std::max(tp - lp, 0.0) * std::max(tn - ln, 0.0));
      if (z < best.z) {
        best.z = z;
        best.stump.feature = int(k);
        best.stump.threshold = d.cuts[k][b];
        best.stump.below = 0.5 * std::log((lp + eps) / (ln + eps));
        best.stump.above =
            0.5 * std::log((std::max(tp - lp, 0.0) + eps) / (std::max(tn - ln, 0.0) + eps));
      }
    }
  }
  if (!std::isfinite(best.z)) {  // no split possible: a constant
    const double c = 0.5 * std::log((tp + eps) / (tn + eps));
    best.stump = {0, 0.0, c, c};
  }
  return best;
}

}  // namespace

LegClassifier train_leg_classifier(std::span<const SegmentFeatures> x, std::span<const char> y,
                                   const BoostOptions& o) {
  if (x.size() != y.size()) throw std::invalid_argument("train_leg_classifier: size mismatch");
  const std::size_t n = x.size();
  const auto n_pos = std::size_t(std::count(y.begin(), y.end(), char(1)));
  if (n_pos == 0 || n_pos == n)
    throw std::invalid_argument("train_leg_classifier: need both legs and other segments");
  const int bins = std::clamp(o.bins, 2, 255);
  // Candidate thresholds per feature: quantiles of the training values.
  std::vector<char> excluded(kSegmentFeatures, 0);
  for (const auto& name : o.excluded_features) {
    const auto it =
        std::find_if(kNames.begin(), kNames.end(), [&](const char* k) { return name == k; });
    if (it == kNames.end()) throw Error("leg classifier: unknown feature '" + name + "'");
    excluded[std::size_t(it - kNames.begin())] = 1;
  }
  Binned d;
  d.cuts.resize(kSegmentFeatures);
  d.bin.assign(kSegmentFeatures, std::vector<std::uint8_t>(n));
  std::vector<double> v(n);
  for (std::size_t k = 0; k < kSegmentFeatures; ++k) {
    for (std::size_t i = 0; i < n; ++i) v[i] = x[i][k];
    std::sort(v.begin(), v.end());
    auto& c = d.cuts[k];
    for (int b = 1; b < bins; ++b)
      c.push_back(v[std::min(n - 1, n * std::size_t(b) / std::size_t(bins))]);
    c.erase(std::unique(c.begin(), c.end()), c.end());
    if (excluded[k]) c.clear();  // one bin: no split on it
    for (std::size_t i = 0; i < n; ++i)
      d.bin[k][i] = std::uint8_t(std::lower_bound(c.begin(), c.end(), x[i][k]) - c.begin());
  }
  const double wp = std::clamp(o.positive_weight, 1e-3, 1 - 1e-3);
  std::vector<double> w(n);
  for (std::size_t i = 0; i < n; ++i)
    w[i] = y[i] ? wp / double(n_pos) : (1 - wp) / double(n - n_pos);
  const double eps = 1.0 / double(n);
  LegClassifier model;
  model.threshold = o.threshold;
  std::vector<char> all(n, 1), side(n);
  for (int round = 0; round < o.rounds; ++round) {
    const auto root = best_split(d, y, w, all, eps);
    BoostTree t;
    t.feature = root.stump.feature;
    t.threshold = root.stump.threshold;
    t.below = {0, 0.0, root.stump.below, root.stump.below};
    t.above = {0, 0.0, root.stump.above, root.stump.above};
    if (o.depth >= 2 && std::isfinite(root.z)) {
      const auto k = std::size_t(t.feature);
      for (std::size_t i = 0; i < n; ++i) side[i] = x[i][k] <= t.threshold;
      t.below = best_split(d, y, w, side, eps).stump;
      for (std::size_t i = 0; i < n; ++i) side[i] = !side[i];
      t.above = best_split(d, y, w, side, eps).stump;
    }
    model.trees.push_back(t);
    double sum = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const double h = t.eval(x[i]);
      w[i] *= std::exp(y[i] ? -h : h);
      sum += w[i];
    }
    for (auto& wi : w) wi /= sum;
  }
  return model;
}

void SegmentSamples::append(const SegmentSamples& o) {
  features.insert(features.end(), o.features.begin(), o.features.end());
  is_leg.insert(is_leg.end(), o.is_leg.begin(), o.is_leg.end());
}

void collect_segment_samples(std::span<const Eigen::Vector2d> ordered,
                             std::span<const Eigen::Vector2d> truth, double range_min_m,
                             double range_max_m, double jump_m, double match_radius_m,
                             double far_radius_m, SegmentSamples& out, bool negatives,
                             const SegmentAugmentationConfig& aug) {
  std::vector<Eigen::Vector2d> pts;
  for (const auto& p : ordered) {
    const double r = p.norm();
    if (p.allFinite() && r >= range_min_m && r <= range_max_m) pts.push_back(p);
  }
  const double step =
      std::isfinite(aug.angular_step_rad) ? aug.angular_step_rad : median_angular_step_rad(pts);
  // Seeded by the samples so far: each scan of a training run draws other copies.
  std::mt19937_64 rng(aug.seed * 0x9E3779B97F4A7C15ull + out.features.size());
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (const auto& [b, e] : split_by_jump(pts, jump_m)) {
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (std::size_t j = b; j < e; ++j) mean += pts[j];
    mean /= double(e - b);
    double nearest = std::numeric_limits<double>::infinity();
    for (const auto& t : truth) nearest = std::min(nearest, (t - mean).norm());
    if (nearest > match_radius_m && (nearest <= far_radius_m || !negatives)) continue;
    const char label = nearest <= match_radius_m ? 1 : 0;
    out.features.push_back(segment_features(pts, b, e));
    out.is_leg.push_back(label);
    for (int k = 0; k < aug.copies && step > 0; ++k) {
      const double lo = std::log(std::max(aug.range_factor_min, 1e-3));
      const double hi = std::log(std::max(aug.range_factor_max, aug.range_factor_min));
      const double range_factor = std::exp(lo + (hi - lo) * unit(rng));
      const double width_factor =
          aug.width_factor_min + (aug.width_factor_max - aug.width_factor_min) * unit(rng);
      const auto r = reseen_segment(pts, b, e, range_factor, width_factor, step, unit(rng),
                                    aug.range_noise_m, rng);
      if (r.end <= r.begin) continue;
      Eigen::Vector2d m = Eigen::Vector2d::Zero();
      for (std::size_t j = r.begin; j < r.end; ++j) m += r.points[j];
      if ((m / double(r.end - r.begin)).norm() > aug.range_max_m) continue;
      out.features.push_back(segment_features(r.points, r.begin, r.end));
      out.is_leg.push_back(label);
    }
  }
}

namespace {
void print_stump(std::ostream& s, const Stump& st) {
  s << "{feature: " << kNames[std::size_t(st.feature)] << ", threshold: " << st.threshold
    << ", below: " << st.below << ", above: " << st.above << "}";
}

int feature_index(const YAML::Node& n, const std::string& source) {
  const auto name = n.as<std::string>();
  const auto it =
      std::find_if(kNames.begin(), kNames.end(), [&](const char* k) { return name == k; });
  if (it == kNames.end()) throw Error(source + ": unknown feature '" + name + "'");
  return int(it - kNames.begin());
}

double finite(const YAML::Node& n, const std::string& source, const char* key) {
  const double v = n[key].as<double>();
  if (!std::isfinite(v)) throw Error(source + ": leg classifier '" + key + "' is not finite");
  return v;
}

Stump parse_stump(const YAML::Node& n, const std::string& source) {
  if (!n.IsMap()) throw Error(source + ": leg classifier stump must be a map");
  return {feature_index(n["feature"], source), finite(n, source, "threshold"),
          finite(n, source, "below"), finite(n, source, "above")};
}
}  // namespace

std::string to_yaml(const LegClassifier& c) {
  std::ostringstream s;
  s.precision(9);
  s << "# fieldlidar leg classifier: Real AdaBoost on depth-1 or depth-2 trees over 2D segment "
       "features\n"
    << "# score = sum over trees of (feature <= threshold ? below : above), where below and above\n"
    << "# are stumps of the same form; a segment is a leg when score > threshold\n"
    << "leg_classifier:\n"
    << "  threshold: " << c.threshold << "\n";
  if (std::isfinite(c.occupied_score_min) || std::isfinite(c.occupied_evidence_min))
    s << "  occupied_leg_score_min: " << c.occupied_score_min << "\n"
      << "  occupied_leg_evidence_min: " << c.occupied_evidence_min << "\n";
  if (c.scan_step_rad > 0)
    s << "  scan_step_deg: " << c.scan_step_rad * 180.0 / M_PI
      << "  # the training scans' angular step\n";
  s << "  trees:\n";
  for (const auto& t : c.trees) {
    s << "    - {feature: " << kNames[std::size_t(t.feature)] << ", threshold: " << t.threshold
      << ",\n       below: ";
    print_stump(s, t.below);
    s << ",\n       above: ";
    print_stump(s, t.above);
    s << "}\n";
  }
  return s.str();
}

LegClassifier leg_classifier_from_yaml(const std::string& text, const std::string& source) {
  LegClassifier c;
  try {
    const YAML::Node root = YAML::Load(text);
    const YAML::Node node = root["leg_classifier"];
    if (!node || !node.IsMap()) throw Error(source + ": no leg_classifier map");
    if (node["threshold"]) c.threshold = finite(node, source, "threshold");
    if (node["occupied_leg_score_min"])
      c.occupied_score_min = finite(node, source, "occupied_leg_score_min");
    if (node["occupied_leg_evidence_min"])
      c.occupied_evidence_min = finite(node, source, "occupied_leg_evidence_min");
    if (node["scan_step_deg"]) {
      const double deg = finite(node, source, "scan_step_deg");
      if (!(deg > 0 && deg <= 10))
        throw Error(source + ": leg_classifier.scan_step_deg must be in (0, 10] deg, is " +
                    std::to_string(deg));
      c.scan_step_rad = deg * M_PI / 180.0;
    }
    const YAML::Node trees = node["trees"];
    if (!trees || !trees.IsSequence() || trees.size() == 0)
      throw Error(source + ": leg_classifier.trees must be a non-empty list");
    for (const auto& n : trees) {
      if (!n.IsMap()) throw Error(source + ": leg classifier tree must be a map");
      BoostTree t;
      t.feature = feature_index(n["feature"], source);
      t.threshold = finite(n, source, "threshold");
      t.below = parse_stump(n["below"], source);
      t.above = parse_stump(n["above"], source);
      c.trees.push_back(t);
    }
  } catch (const YAML::Exception& e) {
    throw Error(source + ": leg classifier YAML: " + e.what());
  }
  return c;
}

}  // namespace fieldlidar::people
