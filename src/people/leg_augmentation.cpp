#include "fieldlidar/people/leg_augmentation.hpp"

#include <algorithm>
#include <cmath>

namespace fieldlidar::people {

double median_angular_step_rad(std::span<const Eigen::Vector2d> scan) {
  std::vector<double> steps;
  steps.reserve(scan.size());
  for (std::size_t i = 1; i < scan.size(); ++i) {
    const double a = std::atan2(scan[i - 1].y(), scan[i - 1].x());
    const double b = std::atan2(scan[i].y(), scan[i].x());
    double d = std::abs(b - a);
    if (d > M_PI) d = 2 * M_PI - d;
    if (d > 0) steps.push_back(d);
  }
  if (steps.empty()) return 0.0;
  auto mid = steps.begin() + std::ptrdiff_t(steps.size() / 2);
  std::nth_element(steps.begin(), mid, steps.end());
  return *mid;
}

AugmentedSegment reseen_segment(std::span<const Eigen::Vector2d> scan, std::size_t begin,
                                std::size_t end, double range_factor, double width_factor,
                                double step, double phase, double range_noise_m,
                                std::mt19937_64& rng) {
  AugmentedSegment out;
  if (end <= begin || end > scan.size()) return out;
  const auto seg = scan.subspan(begin, end - begin);
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  for (const auto& p : seg) c += p;
  c /= double(seg.size());
  const double r = c.norm();
  if (!(r > 1e-6)) return out;
  const Eigen::Vector2d u = c / r, v(-u.y(), u.x());
  const double shift = r * (range_factor - 1.0);
  // Moved points in polar form, bearings relative to the new centroid's (= the old one's).
  const double theta_c = std::atan2(u.y(), u.x());
  std::vector<double> bearing, range;
  for (const auto& p : seg) {
    const Eigen::Vector2d d = p - c;
    const Eigen::Vector2d q = (r + shift) * u + d.dot(u) * u + width_factor * d.dot(v) * v;
    bearing.push_back(std::atan2(q.dot(v), q.dot(u)));
    range.push_back(q.norm());
  }
  // Beam order may run either way round; rays are cast in increasing bearing.
  const bool reversed = bearing.size() > 1 && bearing.back() < bearing.front();
  if (reversed) {
    std::reverse(bearing.begin(), bearing.end());
    std::reverse(range.begin(), range.end());
  }
  std::normal_distribution<double> noise(0.0, std::max(range_noise_m, 1e-12));
  auto ray = [&](double b, double rho) {
    return Eigen::Vector2d(rho * std::cos(theta_c + b), rho * std::sin(theta_c + b));
  };
  std::vector<Eigen::Vector2d> returns;
  if (step > 0 && bearing.size() > 1) {
    std::size_t k = 0;
    for (double b = bearing.front() + std::clamp(phase, 0.0, 1.0) * step; b <= bearing.back();
         b += step) {
      while (k + 2 < bearing.size() && bearing[k + 1] < b) ++k;
      const double span = bearing[k + 1] - bearing[k];
      const double t = span > 1e-12 ? std::clamp((b - bearing[k]) / span, 0.0, 1.0) : 0.0;
      const double rho = range[k] * (1 - t) + range[k + 1] * t;
      returns.push_back(ray(b, rho + (range_noise_m > 0 ? noise(rng) : 0.0)));
    }
  }
  if (returns.empty()) {  // narrower than one step: one return at the middle
    const std::size_t m = bearing.size() / 2;
    returns.push_back(ray(bearing[m], range[m] + (range_noise_m > 0 ? noise(rng) : 0.0)));
  }
  if (reversed) std::reverse(returns.begin(), returns.end());
  // Neighbours: the same range offset to the segment's nearest return, one step outside it.
  const double near_old = [&] {
    double m = std::numeric_limits<double>::infinity();
    for (const auto& p : seg) m = std::min(m, p.norm());
    return m;
  }();
  const double near_new = [&] {
    double m = std::numeric_limits<double>::infinity();
    for (const auto& p : returns) m = std::min(m, p.norm());
    return m;
  }();
  const double dir = reversed ? -1.0 : 1.0;  // bearing direction of the beam order
  auto neighbour = [&](const Eigen::Vector2d& old, const Eigen::Vector2d& edge, double side) {
    const double b = std::atan2(edge.y(), edge.x()) + side * dir * std::max(step, 1e-4);
    const double rho = std::max(old.norm() - near_old + near_new, 0.01);
    return Eigen::Vector2d(rho * std::cos(b), rho * std::sin(b));
  };
  if (begin > 0) out.points.push_back(neighbour(scan[begin - 1], returns.front(), -1.0));
  out.begin = out.points.size();
  out.points.insert(out.points.end(), returns.begin(), returns.end());
  out.end = out.points.size();
  if (end < scan.size()) out.points.push_back(neighbour(scan[end], returns.back(), 1.0));
  return out;
}

}  // namespace fieldlidar::people
