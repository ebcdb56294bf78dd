// Radius from a stem's silhouette seen from the sensor (at the origin of a sweep). The edges of
// what each scan line sees, fitted as two straight lines across the lines (edge_fit), pin the
// width to a fraction of the azimuth step where the lines cross the stem at varied phases of it;
// r = D sin(width / 2) at the axis distance D. Range noise does not enter it as it does a fit
// to a partial arc. A stem whose edges are open on too many lines (an occluder beside it) falls
// back on the per-line widths: the angle between a line's outermost returns plus one step. A
// stem cut by an occluder on every line near breast height is measured on its lines farther up
// or down that see it whole; only without them is its diameter a guess.
#include "silhouette.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "edge_fit.hpp"

namespace fieldlidar::forest {
namespace {

// A tilted stem's horizontal section is an ellipse: seen across the line of sight its half-width
// is r sqrt(1 + s^2), s the axis' slope across that line (tan of the lean in that plane).
double lean_factor(const Cylinder& axis, double min_slope) {
  const Eigen::Vector3d& a = axis.direction;
  const Eigen::Vector2d across(-axis.point.y(), axis.point.x());
  if (!(across.norm() > 0) || !(a.z() > 0)) return 1.0;
  const double s = across.normalized().dot(a.head<2>()) / a.z();
  return std::abs(s) < min_slope ? 1.0 : std::sqrt(1 + s * s);
}

// The edge fit when both edges are closed on enough lines: radius at axis distance dist0.
bool edge_radius(std::span<const EdgeLine> edges, double dist0, const TreeConfig& c,
                 SilhouetteRadius& out) {
  const auto closed = [&](auto side) {
    return std::size_t(std::count_if(edges.begin(), edges.end(), side));
  };
  if (closed([](const EdgeLine& e) { return e.lo_out_rad > -1e29; }) < c.min_silhouette_lines ||
      closed([](const EdgeLine& e) { return e.hi_out_rad < 1e29; }) < c.min_silhouette_lines)
    return false;
  const EdgeWidth w = fit_edge_width(edges, 1.0 / std::max(dist0, 1.0));
  if (!w.ok) return false;
  out.radius_m = dist0 * std::sin(w.width_rad / 2);
  out.lines = edges.size();
  return true;
}

// Mean of the middle half of per-line radii: each line's width is quantised to whole azimuth
// steps, and the lines cross the stem at varied phases of that step (lean, taper), so a mean
// resolves less than a step where a median stays on one of the quantised values.
bool middle_mean(std::vector<double>& radii, std::size_t min_lines, SilhouetteRadius& out) {
  if (radii.size() < min_lines || radii.empty()) return false;
  std::sort(radii.begin(), radii.end());
  const std::size_t cut = radii.size() / 4;
  double sum = 0;
  for (std::size_t k = cut; k < radii.size() - cut; ++k) sum += radii[k];
  out.radius_m = sum / double(radii.size() - 2 * cut);
  out.lines = radii.size();
  return true;
}

}  // namespace

SilhouetteRadius silhouette_radius(const PointCloud& cloud, std::span<const ScanSegment> segments,
                                   const RingIndex& rings, std::span<const std::size_t> segment_ids,
                                   const Cylinder& axis, double base_z, const TreeConfig& c) {
  SilhouetteRadius out;
  out.radius_m = std::numeric_limits<double>::quiet_NaN();
  const Eigen::Vector3d a = axis.direction;
  const double lean = lean_factor(axis, c.min_lean_slope);
  // The width is wanted at breast height: azimuths from the axis bearing there.
  const double z0 = base_z + c.dbh_height_m;
  const Eigen::Vector3d on0 = axis.point + a * ((z0 - axis.point.z()) / a.z());
  const double bearing0 = std::atan2(on0.y(), on0.x()), dist0 = on0.head<2>().norm() / lean;
  // Each line: the two edges of what it sees, as angles from the axis bearing.
  struct LineView {
    double lo = 1e30, hi = -1e30, step = 0, dist = 0;
    bool lo_hidden = false, hi_hidden = false;
    EdgeLine edge;
  };
  const auto see = [&](const ScanSegment& seg) {
    LineView v;
    v.step = rings.step(seg.line);
    const Eigen::Vector3d on = axis.point + a * ((seg.centroid.z() - axis.point.z()) / a.z());
    const double bearing = std::atan2(on.y(), on.x());
    v.dist = on.head<2>().norm() / lean;
    double range = 1e30;
    for (auto i : seg.indices) {
      const auto& p = cloud.points[i];
      const double az = std::remainder(std::atan2(p.y, p.x) - bearing, 2 * std::numbers::pi);
      v.lo = std::min(v.lo, az);
      v.hi = std::max(v.hi, az);
      range = std::min(range, double(std::hypot(p.x, p.y)));
    }
    // An edge whose neighbouring return is nearer by occluder_gap_m is hidden by an occluder.
    const double window = 2.5 * v.step, nearer = range - c.occluder_gap_m;
    v.lo_hidden = rings.beside(seg.line, bearing + v.lo, -1, window) < nearer;
    v.hi_hidden = rings.beside(seg.line, bearing + v.hi, +1, window) < nearer;
    // For the edge fit an edge is closed only when the next column's beam passed behind the
    // whole stem (its far side lies at most a radius behind the nearest return).
    const double shift = std::remainder(bearing - bearing0, 2 * std::numbers::pi);
    const double far_m = range + axis.radius_m + c.edge_clear_m;
    v.edge = {seg.centroid.z() - z0, v.lo + shift, v.hi + shift};
    if (rings.passed_beside(seg.line, bearing + v.lo, -1, v.step, far_m))
      v.edge.lo_out_rad = v.edge.lo_rad - v.step;
    if (rings.passed_beside(seg.line, bearing + v.hi, +1, v.step, far_m))
      v.edge.hi_out_rad = v.edge.hi_rad + v.step;
    return v;
  };
  const auto from_dbh = [&](const ScanSegment& seg) {
    return std::abs(seg.centroid.z() - base_z - c.dbh_height_m);
  };
  // Lines away from breast height (not below silhouette_min_height_m) that see both edges.
  const auto measure_far = [&](SilhouetteRadius& r) {
    std::vector<double> widths;
    std::vector<EdgeLine> whole;
    for (auto s : segment_ids) {
      const auto& seg = segments[s];
      const double d = from_dbh(seg);
      if (d <= c.dbh_window_m || d > c.silhouette_far_window_m || rings.step(seg.line) <= 0 ||
          seg.centroid.z() - base_z < c.silhouette_min_height_m)
        continue;
      const LineView v = see(seg);
      if (v.lo_hidden || v.hi_hidden) continue;
      whole.push_back(v.edge);
      widths.push_back(v.dist * std::sin((v.hi - v.lo + v.step) / 2));
    }
    return edge_radius(whole, dist0, c, r) || middle_mean(widths, c.min_silhouette_lines, r);
  };
  std::vector<double> measured, bounds, guesses;
  std::vector<EdgeLine> edges;
  for (auto s : segment_ids) {
    const auto& seg = segments[s];
    if (from_dbh(seg) > c.dbh_window_m || rings.step(seg.line) <= 0) continue;
    const LineView v = see(seg);
    const double lo = v.lo, hi = v.hi, step = v.step, dist = v.dist;
    const bool lo_hidden = v.lo_hidden, hi_hidden = v.hi_hidden;
    edges.push_back(v.edge);
    if (lo_hidden && hi_hidden) continue;
    if (!lo_hidden && !hi_hidden) {
      measured.push_back(dist * std::sin((hi - lo + step) / 2));
      continue;
    }
    // One edge hidden: what is seen bounds the width from below. When it reaches at least a step
    // past the axis bearing, that bearing is held by the stem's near side and the free edge's
    // angle from it is half the width; a narrower sliver leaves the bearing, and so the width,
    // loose.
    bounds.push_back(dist * std::sin((hi - lo) / 2));
    const double half = dist * std::sin((lo_hidden ? hi : -lo) + step / 2);
    guesses.push_back(half);
    if ((lo_hidden ? -lo : hi) >= step) measured.push_back(half);
  }
  // Both edges closed on enough lines: the edge fit. The slope of the edges is bounded by a
  // lean of 45 degrees across the line of sight.
  if (edge_radius(edges, dist0, c, out)) return out;
  if (!bounds.empty()) {
    // The second widest: one line widened by a branch beside the occluder bounds nothing.
    std::sort(bounds.begin(), bounds.end());
    if (bounds.size() >= 2) out.lower_bound_m = bounds[bounds.size() - 2];
  }
  // A line narrower than what the occluded lines show was cut short in height (the top of a
  // shrub across it, a missed return) and says nothing of the width.
  std::erase_if(measured, [&](double r) { return r < out.lower_bound_m; });
  out.lines = measured.size();
  if (measured.size() < c.min_silhouette_lines) {
    // Every line near breast height cut by an occluder (a shrub, a low branch, a nearer stem):
    // the stem where the lines see it whole, above or below, rather than a guess that rests on
    // the bearing of a circle fitted to the sliver (drawn into the sliver, it reads the
    // diameter as little more than the sliver's width). Only for a stem the occluded lines saw
    // (one kept with a guess before): those lines replace a guess, they make no new tree.
    if (!guesses.empty() && measure_far(out)) return out;
    if (!guesses.empty()) {
      std::nth_element(guesses.begin(), guesses.begin() + guesses.size() / 2, guesses.end());
      out.guess_m = std::max(guesses[guesses.size() / 2], out.lower_bound_m);
    }
    return out;
  }
  middle_mean(measured, c.min_silhouette_lines, out);
  return out;
}

}  // namespace fieldlidar::forest
