#include "fieldlidar/follow/boundary.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "fieldlidar/core/segment_distance.hpp"

namespace fieldlidar::follow {

namespace {

void douglas_peucker(const std::vector<Eigen::Vector2d>& pts, std::size_t first, std::size_t last,
                     double tol, std::vector<bool>& keep) {
  if (last <= first + 1) return;
  double best = -1;
  std::size_t idx = first;
  for (std::size_t i = first + 1; i < last; ++i) {
    const double d = point_segment_distance(pts[i], pts[first], pts[last]);
    if (d > best) {
      best = d;
      idx = i;
    }
  }
  if (best > tol) {
    keep[idx] = true;
    douglas_peucker(pts, first, idx, tol, keep);
    douglas_peucker(pts, idx, last, tol, keep);
  }
}

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

std::vector<Eigen::Vector2d> sample_closed(const std::vector<Eigen::Vector2d>& ring, double step) {
  std::vector<Eigen::Vector2d> out;
  for (std::size_t i = 0; i < ring.size(); ++i) {
    const Eigen::Vector2d a = ring[i], b = ring[(i + 1) % ring.size()];
    const int n = std::max(1, int(std::ceil((b - a).norm() / step)));
    for (int k = 0; k < n; ++k) out.push_back(a + (b - a) * (double(k) / n));
  }
  return out;
}

}  // namespace

void BoundaryRecorder::record(const Eigen::Vector2d& p, bool following) {
  // seed 000, step 8: record while following; a stop (safety or loss) pauses the recording.
  if (!following || !p.allFinite()) return;
  if (points_.empty()) {
    points_.push_back(p);
    return;
  }
  const double d = (p - points_.back()).norm();
  if (d >= config_.record_spacing_m) {
    points_.push_back(p);
    length_m_ += d;
  }
}

BoundaryPolygon BoundaryRecorder::close() const {
  BoundaryPolygon poly;
  poly.raw_points = points_.size();
  // Closing joins the end to the start: the ring is implicit, the last edge is that join.
  poly.vertices =
      simplify_closed(points_, config_.simplify_tolerance_m, config_.min_vertex_spacing_m);
  if (poly.vertices.size() >= 3) {
    if (signed_area(poly.vertices) < 0) std::reverse(poly.vertices.begin(), poly.vertices.end());
    poly.area_m2 = std::abs(signed_area(poly.vertices));
    for (std::size_t i = 0; i < poly.vertices.size(); ++i)
      poly.perimeter_m += (poly.vertices[(i + 1) % poly.vertices.size()] - poly.vertices[i]).norm();
    poly.self_intersections = find_self_intersections(poly.vertices);
  }
  return poly;
}

std::vector<Eigen::Vector2d> simplify_closed(const std::vector<Eigen::Vector2d>& ring_in,
                                             double tol, double min_spacing) {
  std::vector<Eigen::Vector2d> ring;
  for (const auto& p : ring_in)
    if (ring.empty() || (p - ring.back()).norm() >= min_spacing) ring.push_back(p);
  while (ring.size() > 1 && (ring.back() - ring.front()).norm() < min_spacing) ring.pop_back();
  if (ring.size() < 4) return ring;
  // Split the ring at the start and at the vertex farthest from it, simplify both halves.
  std::size_t far = 0;
  for (std::size_t i = 1; i < ring.size(); ++i)
    if ((ring[i] - ring[0]).norm() > (ring[far] - ring[0]).norm()) far = i;
  std::vector<Eigen::Vector2d> closed = ring;
  closed.push_back(ring[0]);
  std::vector<bool> keep(closed.size(), false);
  keep[0] = keep[far] = keep.back() = true;
  douglas_peucker(closed, 0, far, tol, keep);
  douglas_peucker(closed, far, closed.size() - 1, tol, keep);
  std::vector<Eigen::Vector2d> out;
  for (std::size_t i = 0; i + 1 < closed.size(); ++i)
    if (keep[i]) out.push_back(closed[i]);
  // The start vertex itself may be collinear with its neighbours.
  if (out.size() > 3 && point_segment_distance(out[0], out.back(), out[1]) <= tol)
    out.erase(out.begin());
  return out;
}

std::vector<SelfIntersection> find_self_intersections(const std::vector<Eigen::Vector2d>& ring) {
  std::vector<SelfIntersection> out;
  const std::size_t n = ring.size();
  if (n < 4) return out;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d p = ring[i], r = ring[(i + 1) % n] - p;
    for (std::size_t j = i + 2; j < n; ++j) {
      if (i == 0 && j == n - 1) continue;  // adjacent through the closing edge
      const Eigen::Vector2d q = ring[j], s = ring[(j + 1) % n] - q;
      const double den = cross(r, s);
      if (std::abs(den) < 1e-15) continue;  // parallel (collinear overlaps are not reported)
      const double t = cross(q - p, s) / den, u = cross(q - p, r) / den;
      if (t >= 0 && t <= 1 && u >= 0 && u <= 1) out.push_back({i, j, p + t * r});
    }
  }
  return out;
}

double signed_area(const std::vector<Eigen::Vector2d>& ring) {
  double a = 0;
  for (std::size_t i = 0; i < ring.size(); ++i) a += cross(ring[i], ring[(i + 1) % ring.size()]);
  return a / 2;
}

double distance_to_closed(const Eigen::Vector2d& p, const std::vector<Eigen::Vector2d>& ring) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < ring.size(); ++i)
    best = std::min(best, point_segment_distance(p, ring[i], ring[(i + 1) % ring.size()]));
  return best;
}

PolygonDistance compare_closed(const std::vector<Eigen::Vector2d>& polygon,
                               const std::vector<Eigen::Vector2d>& reference, double step) {
  PolygonDistance d;
  if (polygon.size() < 2 || reference.size() < 2) {
    d.mean_m = d.hausdorff_m = std::numeric_limits<double>::infinity();
    return d;
  }
  const auto a = sample_closed(polygon, step), b = sample_closed(reference, step);
  double sum = 0;
  for (const auto& p : a) {
    const double e = distance_to_closed(p, reference);
    sum += e;
    d.hausdorff_m = std::max(d.hausdorff_m, e);
  }
  d.mean_m = sum / double(a.size());
  for (const auto& p : b) d.hausdorff_m = std::max(d.hausdorff_m, distance_to_closed(p, polygon));
  return d;
}

}  // namespace fieldlidar::follow
