// Radius from a stem's silhouette seen from the sensor (at the origin of a sweep): on each scan
// line, the angle between its outermost returns plus one azimuth step, and r = D sin(angle / 2)
// at the axis distance D. Range noise does not enter it as it does a fit to a partial arc.
#include "silhouette.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace fieldlidar::forest {

SilhouetteRadius silhouette_radius(const PointCloud& cloud, std::span<const ScanSegment> segments,
                                   const RingIndex& rings, std::span<const std::size_t> segment_ids,
                                   const Cylinder& axis, double base_z, const TreeConfig& c) {
  SilhouetteRadius out;
  out.radius_m = std::numeric_limits<double>::quiet_NaN();
  const Eigen::Vector3d a = axis.direction;
  // Each line: the two edges of what it sees, as angles from the axis bearing.
  std::vector<double> measured, bounds, guesses;
  for (auto s : segment_ids) {
    const auto& seg = segments[s];
    const double step = rings.step(seg.line);
    if (std::abs(seg.centroid.z() - base_z - c.dbh_height_m) > c.dbh_window_m || step <= 0)
      continue;
    const Eigen::Vector3d on = axis.point + a * ((seg.centroid.z() - axis.point.z()) / a.z());
    const double bearing = std::atan2(on.y(), on.x()), dist = on.head<2>().norm();
    double lo = 1e30, hi = -1e30, range = 1e30;
    for (auto i : seg.indices) {
      const auto& p = cloud.points[i];
      const double az = std::remainder(std::atan2(p.y, p.x) - bearing, 2 * std::numbers::pi);
      lo = std::min(lo, az);
      hi = std::max(hi, az);
      range = std::min(range, double(std::hypot(p.x, p.y)));
    }
    // An edge whose neighbouring return is nearer by occluder_gap_m is hidden by an occluder.
    const double window = 2.5 * step, nearer = range - c.occluder_gap_m;
    const bool lo_hidden = rings.beside(seg.line, bearing + lo, -1, window) < nearer;
    const bool hi_hidden = rings.beside(seg.line, bearing + hi, +1, window) < nearer;
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
    if (!guesses.empty()) {
      std::nth_element(guesses.begin(), guesses.begin() + guesses.size() / 2, guesses.end());
      out.guess_m = std::max(guesses[guesses.size() / 2], out.lower_bound_m);
    }
    return out;
  }
  std::sort(measured.begin(), measured.end());
  // Mean of the middle half: each line's width is quantised to whole azimuth steps, and the lines
  // cross the stem at varied phases of that step (lean, taper), so a mean resolves less than a
  // step where a median stays on one of the quantised values.
  const std::size_t cut = measured.size() / 4;
  double sum = 0;
  for (std::size_t k = cut; k < measured.size() - cut; ++k) sum += measured[k];
  out.radius_m = sum / double(measured.size() - 2 * cut);
  return out;
}

}  // namespace fieldlidar::forest
