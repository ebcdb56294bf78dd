#pragma once
// Analytic ray intersections for the moving people (few primitives, not in the static BVH).

#include <cmath>

#include <Eigen/Core>

#include "fieldlidar/sim/walker.hpp"

namespace fieldlidar::sim::detail {

/// Distance along the unit ray (o, d) to the first hit with the capsule beyond t_min, or a
/// negative value on a miss; `normal` receives the outward unit normal at the hit.
inline double ray_capsule(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Capsule& c,
                          Eigen::Vector3d& normal) {
  const Eigen::Vector3d ba = c.b - c.a;
  const Eigen::Vector3d oa = o - c.a;
  const double baba = ba.dot(ba);
  const double r2 = c.radius_m * c.radius_m;
  double t = -1.0;
  if (baba > 1e-12) {
    const double bard = ba.dot(d), baoa = ba.dot(oa), rdoa = d.dot(oa), oaoa = oa.dot(oa);
    const double a = baba - bard * bard;
    const double b = baba * rdoa - baoa * bard;
    const double cc = baba * oaoa - baoa * baoa - r2 * baba;
    const double h = b * b - a * cc;
    if (h < 0) return -1.0;
    if (a > 1e-12) {
      t = (-b - std::sqrt(h)) / a;
      const double y = baoa + t * bard;
      if (y > 0 && y < baba && t > 0) {
        const Eigen::Vector3d p = o + t * d;
        normal = (p - (c.a + (y / baba) * ba)) / c.radius_m;
        return t;
      }
    }
  }
  // End spheres: test both (the nearer positive hit wins).
  double best = -1.0;
  for (const Eigen::Vector3d* centre : {&c.a, &c.b}) {
    const Eigen::Vector3d oc = o - *centre;
    const double b = d.dot(oc);
    const double h = b * b - (oc.dot(oc) - r2);
    if (h < 0) continue;
    const double ts = -b - std::sqrt(h);
    if (ts > 0 && (best < 0 || ts < best)) {
      best = ts;
      normal = (o + ts * d - *centre) / c.radius_m;
    }
    if (baba <= 1e-12) break;
  }
  return best;
}

/// True when the unit ray passes within `radius` of `centre` ahead of the origin.
inline bool ray_near_sphere(const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                            const Eigen::Vector3d& centre, double radius) {
  const Eigen::Vector3d oc = centre - o;
  const double along = oc.dot(d);
  if (along < -radius) return false;
  return (oc - along * d).squaredNorm() <= radius * radius;
}

}  // namespace fieldlidar::sim::detail
