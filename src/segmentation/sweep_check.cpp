// Whether a cloud can be one sweep of a sensor at its origin: the robust ground grows its polar
// grid out from the origin and needs the sensor there, above its ground. A survey (a LAS tile in
// a local frame, a terrestrial plot, a merged map) fails that and takes the grid ground instead.

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "fieldlidar/segmentation/ground.hpp"
#include "polar_grid.hpp"

namespace fieldlidar::segmentation {

SweepCheck check_sweep(const PointCloud& cloud) {
  if (cloud.fields.ring && cloud.ring_count() > 1) return {true, "ring field"};
  if (cloud.is_organized()) return {true, "organised (rings x columns)"};
  constexpr int kSectors = 16;
  constexpr float kNear = 2.f, kFar = 20.f;
  std::array<std::size_t, kSectors> per_sector{};
  std::vector<float> near_z;
  std::size_t valid = 0;
  const std::size_t stride = std::max<std::size_t>(1, cloud.size() / 20000);
  for (std::size_t i = 0; i < cloud.size(); i += stride) {
    const Point& p = cloud.points[i];
    if (!valid_point(p)) continue;
    ++valid;
    const float az = fast_atan2(p.y, p.x) + float(std::numbers::pi);
    ++per_sector[std::size_t(
        std::clamp(int(az * float(kSectors / (2 * std::numbers::pi))), 0, kSectors - 1))];
    const float rho = std::hypot(p.x, p.y);
    if (rho >= kNear && rho < kFar) near_z.push_back(p.z);
  }
  if (valid == 0) return {false, "no valid point"};
  // A sector counts when it holds at least 1/4 of an even share of the points.
  const std::size_t filled =
      std::size_t(std::count_if(per_sector.begin(), per_sector.end(),
                                [valid](std::size_t n) { return n * 4 * kSectors >= valid; }));
  if (filled < kSectors / 2)
    return {false, "the points do not surround the origin (" + std::to_string(filled) + " of " +
                       std::to_string(kSectors) + " azimuth sectors)"};
  if (near_z.size() < 20)
    return {false,
            "too few returns 2-20 m around the origin (" + std::to_string(near_z.size()) + ")"};
  const auto low = near_z.begin() + std::ptrdiff_t(near_z.size() / 20);
  std::nth_element(near_z.begin(), low, near_z.end());
  if (!(*low <= -0.1f && *low >= -10.f))
    return {false, "the origin is not above the ground near it (lowest returns 2-20 m out at z = " +
                       std::to_string(int(std::lround(*low))) + " m)"};
  return {true, "points around the origin, which stands above them"};
}

}  // namespace fieldlidar::segmentation
