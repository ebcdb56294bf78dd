#include <algorithm>
#include <cmath>
#include <numbers>

#include "fieldlidar/core/pose2.hpp"
#include "fieldlidar/segmentation/range_image.hpp"
#include "polar_grid.hpp"

namespace fieldlidar::segmentation {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr double kMaxBackStepRad = 0.2;

double elevation_of(const Point& p) {
  return std::atan2(double(p.z), std::hypot(double(p.x), double(p.y)));
}

double median(std::vector<double>& v) {
  if (v.empty()) return 0.0;
  auto mid = v.begin() + v.size() / 2;
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

// Maps scan-order ring numbers so that ring 0 is the lowest beam (the order of the sensor's
// firing table is either top-down, as in KITTI, or bottom-up).
bool orient_rings(const PointCloud& cloud, std::vector<std::uint16_t>& rings, std::size_t count) {
  std::vector<std::vector<double>> elev(count);
  for (std::size_t i = 0; i < cloud.size(); ++i)
    if (rings[i] != Point::kNoRing && elev[rings[i]].size() < 64)
      elev[rings[i]].push_back(elevation_of(cloud.points[i]));
  std::vector<double> med(count);
  for (std::size_t r = 0; r < count; ++r) {
    if (elev[r].empty()) return false;
    med[r] = median(elev[r]);
  }
  // Mostly monotonic is enough: beams of a non-uniform table interleave slightly.
  std::size_t up = 0, down = 0;
  for (std::size_t r = 1; r < count; ++r) (med[r] > med[r - 1] ? up : down)++;
  if (std::max(up, down) + 1 < count * 9 / 10) return false;
  if (down > up)
    for (auto& r : rings)
      if (r != Point::kNoRing) r = static_cast<std::uint16_t>(count - 1 - r);
  return true;
}

bool rings_from_scan_order(const PointCloud& cloud, std::size_t count,
                           std::vector<std::uint16_t>& rings) {
  // Scan direction: the sign of most small azimuth steps between consecutive returns.
  long votes = 0;
  double prev = 0;
  bool have_prev = false;
  for (std::size_t i = 0; i < cloud.size() && std::labs(votes) < 2000; ++i) {
    const Point& p = cloud.points[i];
    if (!valid_point(p)) continue;
    const double az = fast_atan2(p.y, p.x);
    if (have_prev) {
      const double d = wrap_angle(az - prev);
      if (std::abs(d) < 0.1) votes += d > 0 ? 1 : -1;
    }
    prev = az;
    have_prev = true;
  }
  const double dir = votes >= 0 ? 1.0 : -1.0;
  // A ring ends when the azimuth, measured in the scan direction from where the sweep began (the
  // first return), falls back: every ring of a spinning sensor starts at the same azimuth.
  std::size_t ring = 0;
  bool started = false;
  double start = 0, last = 0;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Point& p = cloud.points[i];
    if (!valid_point(p)) continue;
    const double az = fast_atan2(p.y, p.x);
    if (!started) {
      start = az - dir * 1e-3;  // tolerate jitter of the next rings' first returns
      started = true;
    }
    double a = dir * (az - start);  // in (-2 pi, 2 pi)
    if (a < 0) a += kTwoPi;
    // Within a ring the azimuth only moves forward (up to jitter of a few milliradians); a step
    // back marks the next ring even when a ring saw returns over part of the turn only.
    if (a < last - kMaxBackStepRad && ++ring >= count) return false;
    last = a;
    rings[i] = static_cast<std::uint16_t>(ring);
  }
  return ring + 1 == count && orient_rings(cloud, rings, count);
}

// Organised dumps without a ring field store the image row after row (i / width) or column after
// column (i % rings, as RELLIS-3D's Ouster .bin files do).
bool rings_from_index(const PointCloud& cloud, std::size_t count, bool column_major,
                      std::vector<std::uint16_t>& rings) {
  if (count == 0 || cloud.size() % count != 0 || cloud.size() < count) return false;
  const std::size_t width = cloud.size() / count;
  for (std::size_t i = 0; i < cloud.size(); ++i)
    if (valid_point(cloud.points[i]))
      rings[i] = static_cast<std::uint16_t>(column_major ? i % count : i / width);
  return orient_rings(cloud, rings, count);
}

}  // namespace

RingEstimate estimate_rings(const PointCloud& cloud, const SensorModel& sensor) {
  RingEstimate out;
  out.rings.assign(cloud.size(), Point::kNoRing);
  const std::size_t count = sensor.rings();
  if (cloud.fields.ring) {
    for (std::size_t i = 0; i < cloud.size(); ++i)
      if (valid_point(cloud.points[i])) out.rings[i] = cloud.points[i].ring;
    out.method = RingEstimate::Method::kRingField;
    return out;
  }
  if (count > 1 && sensor.kind == SensorModel::Kind::kSpinning) {
    if (cloud.is_organized() && cloud.height == count) {
      for (std::size_t i = 0; i < cloud.size(); ++i)
        if (valid_point(cloud.points[i]))
          out.rings[i] = static_cast<std::uint16_t>(i / cloud.width);
      if (orient_rings(cloud, out.rings, count)) {
        out.method = RingEstimate::Method::kIndexRows;
        return out;
      }
      std::fill(out.rings.begin(), out.rings.end(), Point::kNoRing);
    }
    if (rings_from_scan_order(cloud, count, out.rings)) {
      out.method = RingEstimate::Method::kScanOrder;
      return out;
    }
    std::fill(out.rings.begin(), out.rings.end(), Point::kNoRing);
    if (rings_from_index(cloud, count, false, out.rings)) {
      out.method = RingEstimate::Method::kIndexRows;
      return out;
    }
    std::fill(out.rings.begin(), out.rings.end(), Point::kNoRing);
    if (rings_from_index(cloud, count, true, out.rings)) {
      out.method = RingEstimate::Method::kIndexColumns;
      return out;
    }
    std::fill(out.rings.begin(), out.rings.end(), Point::kNoRing);
  }
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Point& p = cloud.points[i];
    if (valid_point(p))
      out.rings[i] = static_cast<std::uint16_t>(sensor.nearest_ring(elevation_of(p)));
  }
  out.method = RingEstimate::Method::kNearestBeam;
  return out;
}

}  // namespace fieldlidar::segmentation
