// Reeds–Shepp shortcutting: from each anchor pose of the path (about anchor_spacing_m apart, cusps
// and ends included), the farthest later anchor whose joining curve is obstacle-free and cheaper
// than the sub-path it replaces; tries move the far end closer by a constant factor, so an anchor
// costs O(log n) curves.

#include "shortcut.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "fieldlidar/planning/reeds_shepp.hpp"

namespace fieldlidar::planning {
namespace {

// A coarse look at the curve (about every 0.8 m) before it is sampled finely.
bool coarse_free(const Pose2& from, const RsCurve& curve, double radius_m, const PlanningMap& map) {
  const int n = int(curve.length_m / 0.8);
  for (int k = 1; k <= n; ++k)
    if (!map.pose_free(rs_pose_at(from, curve, radius_m, curve.length_m * k / (n + 1))))
      return false;
  return true;
}

}  // namespace

bool samples_free(const Path& s, const PlanningMap& map) {
  for (std::size_t k = 8; k < s.size(); k += 8)
    if (!map.pose_free(s[k].pose)) return false;
  for (std::size_t k = 1; k < s.size(); ++k)
    if (k % 8 != 0 && !map.pose_free(s[k].pose)) return false;
  return true;
}

Path shortcut_path(const Path& path, const PlanningMap& map, const ShortcutConfig& c,
                   ShortcutReport* report) {
  ShortcutReport r;
  const std::size_t n = path.size();
  const double pen = c.cost.direction_change_penalty_m;
  // prefix[k]: cost of steps 1..k; switches[k]: direction switches among steps 1..k
  std::vector<double> prefix(n, 0.0);
  std::vector<int> switches(n, 0);
  for (std::size_t k = 1; k < n; ++k) {
    prefix[k] = prefix[k - 1] + step_cost(map, c.cost, path[k - 1], path[k]);
    if (k >= 2) switches[k] = switches[k - 1] + (path[k].reverse != path[k - 1].reverse);
  }
  r.cost_before = n > 0 ? prefix[n - 1] + pen * switches[n - 1] : 0.0;
  if (n < 3) {
    r.cost_after = r.cost_before;
    if (report) *report = r;
    return path;
  }
  std::vector<std::size_t> anchors{0};
  double since = 0.0;
  for (std::size_t k = 1; k + 1 < n; ++k) {
    since += std::hypot(path[k].pose.x_m - path[k - 1].pose.x_m,
                        path[k].pose.y_m - path[k - 1].pose.y_m);
    if (since >= c.anchor_spacing_m || path[k].reverse != path[k + 1].reverse) {
      anchors.push_back(k);
      since = 0.0;
    }
  }
  anchors.push_back(n - 1);

  // The cost of sub-path i..j, with the switches at its ends.
  auto sub_cost = [&](std::size_t i, std::size_t j) {
    int sw = switches[j] - switches[i + 1];
    if (i >= 1) sw += path[i].reverse != path[i + 1].reverse;
    if (j + 1 < n) sw += path[j + 1].reverse != path[j].reverse;
    return prefix[j] - prefix[i] + pen * sw;
  };
  auto curve_cost = [&](const Path& s, std::size_t i, std::size_t j) {
    double cost = 0.0;
    int sw = 0;
    for (std::size_t k = 1; k < s.size(); ++k) {
      cost += step_cost(map, c.cost, s[k - 1], s[k]);
      if (k >= 2) sw += s[k].reverse != s[k - 1].reverse;
    }
    if (i >= 1) sw += path[i].reverse != s[1].reverse;
    if (j + 1 < n) sw += path[j + 1].reverse != s.back().reverse;
    return cost + pen * sw;
  };

  Path out{path[0]};
  std::size_t a = 0;
  while (a + 1 < anchors.size()) {
    const std::size_t i = anchors[a];
    bool replaced = false;
    for (std::size_t far = anchors.size() - 1; far >= a + 2;) {
      const std::size_t j = anchors[far];
      ++r.tried;
      const double before = sub_cost(i, j);
      const RsCurve curve = reeds_shepp(path[i].pose, path[j].pose, c.radius_m);
      // every multiplier of the cost is >= 1: a curve no shorter cannot cost less (the sampled
      // polyline is a hair shorter than the curve, hence the margin)
      if (curve.length_m * (1.0 - 1e-3) < before &&
          coarse_free(path[i].pose, curve, c.radius_m, map)) {
        Path s = rs_sample(path[i].pose, curve, c.radius_m, c.resolution_m);
        s.back().pose = path[j].pose;
        if (s.size() >= 2 && curve_cost(s, i, j) < before - 1e-6 && samples_free(s, map)) {
          out.insert(out.end(), s.begin() + 1, s.end());
          ++r.replaced;
          a = far;
          replaced = true;
          break;
        }
      }
      far = std::min(far - 1, a + std::size_t(double(far - a) * c.shrink));
    }
    if (!replaced) {
      out.insert(out.end(), path.begin() + long(i) + 1, path.begin() + long(anchors[a + 1]) + 1);
      ++a;
    }
  }
  out[0].reverse = out[1].reverse;
  double cost = 0.0;
  int sw = 0;
  for (std::size_t k = 1; k < out.size(); ++k) {
    cost += step_cost(map, c.cost, out[k - 1], out[k]);
    if (k >= 2) sw += out[k].reverse != out[k - 1].reverse;
  }
  r.cost_after = cost + pen * sw;
  if (report) *report = r;
  return out;
}

}  // namespace fieldlidar::planning
