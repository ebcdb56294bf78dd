#pragma once
// Synthetic 2D laser scans with exact geometry: circles (legs, posts) and line walls ray-cast from
// the origin at a fixed angular resolution.

#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include <Eigen/Core>

namespace fieldlidar::test {

struct Circle {
  Eigen::Vector2d center;
  double radius;
};
struct Wall {
  Eigen::Vector2d a, b;
};

inline std::optional<double> hit_circle(const Eigen::Vector2d& dir, const Circle& c) {
  const double b = dir.dot(c.center);
  const double disc = b * b - (c.center.squaredNorm() - c.radius * c.radius);
  if (disc < 0) return std::nullopt;
  const double t = b - std::sqrt(disc);
  return t > 0 ? std::optional<double>(t) : std::nullopt;
}

inline std::optional<double> hit_wall(const Eigen::Vector2d& dir, const Wall& w) {
  const Eigen::Vector2d e = w.b - w.a;
  const double den = dir.x() * (-e.y()) - dir.y() * (-e.x());
  if (std::abs(den) < 1e-12) return std::nullopt;
  // Solve t*dir = a + s*e.
  const double t = (w.a.x() * (-e.y()) - w.a.y() * (-e.x())) / den;
  const double s = (dir.x() * w.a.y() - dir.y() * w.a.x()) / den;
  if (t <= 0 || s < 0 || s > 1) return std::nullopt;
  return t;
}

/// Points of one scan over [-fov/2, fov/2] in beam order (no-returns skipped).
inline std::vector<Eigen::Vector2d> cast_scan(const std::vector<Circle>& circles,
                                              const std::vector<Wall>& walls,
                                              double resolution_rad = 0.33 * M_PI / 180,
                                              double fov_rad = M_PI, double max_range = 20) {
  std::vector<Eigen::Vector2d> pts;
  for (double a = -fov_rad / 2; a <= fov_rad / 2; a += resolution_rad) {
    const Eigen::Vector2d dir(std::cos(a), std::sin(a));
    double best = std::numeric_limits<double>::infinity();
    for (const auto& c : circles)
      if (auto t = hit_circle(dir, c)) best = std::min(best, *t);
    for (const auto& w : walls)
      if (auto t = hit_wall(dir, w)) best = std::min(best, *t);
    if (best < max_range) pts.push_back(dir * best);
  }
  return pts;
}

}  // namespace fieldlidar::test
