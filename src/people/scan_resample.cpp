#include "fieldlidar/people/scan_resample.hpp"

#include <algorithm>
#include <cmath>

namespace fieldlidar::people {

namespace {

constexpr double kMaxStep_rad = 0.1;  ///< a larger bearing difference is a gap or a wrap

double bearing(const Eigen::Vector2d& p) {
  return std::atan2(p.y(), p.x());
}

}  // namespace

double scan_step_rad(std::span<const Eigen::Vector2d> points) {
  std::vector<double> steps;
  steps.reserve(points.size());
  for (std::size_t i = 1; i < points.size(); ++i) {
    const double d = bearing(points[i]) - bearing(points[i - 1]);
    if (d > 0 && d < kMaxStep_rad) steps.push_back(d);
  }
  if (steps.size() < 10) return 0.0;
  const auto q = steps.begin() + std::ptrdiff_t(steps.size() / 4);
  std::nth_element(steps.begin(), q, steps.end());
  return *q;
}

std::vector<Eigen::Vector2d> resample_scan(std::span<const Eigen::Vector2d> points, double step_rad,
                                           double jump_m) {
  std::vector<Eigen::Vector2d> out;
  if (!(step_rad > 0)) return {points.begin(), points.end()};
  out.reserve(2 * points.size());
  const std::size_t n = points.size();
  std::size_t i = 0;
  while (i < n) {
    // One surface: consecutive points closer than jump_m, bearings rising by under 0.1 rad.
    std::size_t j = i;
    while (j + 1 < n && (points[j + 1] - points[j]).norm() < jump_m) {
      const double d = bearing(points[j + 1]) - bearing(points[j]);
      if (!(d > 0 && d < kMaxStep_rad)) break;
      ++j;
    }
    if (j == i) {
      out.push_back(points[i++]);
      continue;
    }
    const double a0 = bearing(points[i]), a1 = bearing(points[j]);
    const int m = std::max(1, int(std::lround((a1 - a0) / step_rad)));
    std::size_t k = i;  // points[k], points[k + 1] bracket the sample
    for (int s = 0; s <= m; ++s) {
      if (s == 0 || s == m) {
        out.push_back(points[s == 0 ? i : j]);
        continue;
      }
      const double a = a0 + (a1 - a0) * s / m;
      while (k + 1 < j && bearing(points[k + 1]) <= a) ++k;
      const double ak = bearing(points[k]), ak1 = bearing(points[k + 1]);
      const double f = std::clamp((a - ak) / (ak1 - ak), 0.0, 1.0);
      const double r = (1 - f) * points[k].norm() + f * points[k + 1].norm();
      out.emplace_back(r * std::cos(a), r * std::sin(a));
    }
    i = j + 1;
  }
  return out;
}

}  // namespace fieldlidar::people
