#pragma once
// Helpers shared by the segmentation tests: a KITTI-layout reader (so these tests do not depend
// on io/), synthetic scans with exact truth, and partition comparison.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <vector>

#include "fieldlidar/core/point_cloud.hpp"
#include "fieldlidar/core/sensor_model.hpp"

namespace fieldlidar::segmentation::test {

/// float32 x y z intensity per point; no ring field (KITTI and RELLIS-3D .bin).
inline PointCloud read_bin(const std::filesystem::path& path) {
  std::ifstream f(path, std::ios::binary | std::ios::ate);
  const auto bytes = static_cast<std::size_t>(f.tellg());
  f.seekg(0);
  std::vector<float> d(bytes / sizeof(float));
  f.read(reinterpret_cast<char*>(d.data()), std::streamsize(d.size() * sizeof(float)));
  PointCloud c;
  for (std::size_t i = 0; i + 3 < d.size(); i += 4) {
    Point p;
    p.x = d[i];
    p.y = d[i + 1];
    p.z = d[i + 2];
    p.intensity = d[i + 3];
    c.points.push_back(p);
  }
  c.width = std::uint32_t(c.size());
  c.fields.intensity = true;
  return c;
}

inline std::vector<std::uint32_t> read_label_file(const std::filesystem::path& path) {
  std::ifstream f(path, std::ios::binary | std::ios::ate);
  const auto bytes = static_cast<std::size_t>(f.tellg());
  f.seekg(0);
  std::vector<std::uint32_t> l(bytes / 4);
  f.read(reinterpret_cast<char*>(l.data()), std::streamsize(bytes));
  return l;
}

/// One object of a synthetic scene: an axis-aligned box standing on the ground.
struct Box {
  Eigen::Vector3d min, max;
};

/// A spinning sensor's sweep over ground z = height_at(x, y) (given in the lidar frame) with boxes,
/// ray-marched analytically: per beam the nearest box hit or ground hit. Labels: 1 ground, 2+k
/// box k. Points in ring-major scan order, ring field set when `with_ring`.
template <class GroundZ>
PointCloud synthetic_scan(const SensorModel& sensor, GroundZ ground_z,
                          const std::vector<Box>& boxes, bool with_ring = true,
                          double noise_m = 0.0, std::uint32_t seed = 1) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, noise_m > 0 ? noise_m : 1e-12);
  PointCloud cloud;
  cloud.fields.ring = with_ring;
  cloud.fields.label = true;
  const int cols = sensor.columns;
  for (std::size_t ring = 0; ring < sensor.rings(); ++ring) {
    const double el = sensor.beam_altitudes_rad[ring];
    for (int c = 0; c < cols; ++c) {
      const double az = 2.0 * std::numbers::pi * c / cols - std::numbers::pi + 1e-4;
      const Eigen::Vector3d d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az),
                              std::sin(el));
      double best = sensor.max_range_m;
      std::uint32_t label = 0;
      for (std::size_t k = 0; k < boxes.size(); ++k) {  // slab test
        double t0 = 0, t1 = best;
        bool hit = true;
        for (int a = 0; a < 3 && hit; ++a) {
          if (std::abs(d(a)) < 1e-12) {
            hit = boxes[k].min(a) <= 0 && 0 <= boxes[k].max(a);
            continue;
          }
          double ta = boxes[k].min(a) / d(a), tb = boxes[k].max(a) / d(a);
          if (ta > tb) std::swap(ta, tb);
          t0 = std::max(t0, ta);
          t1 = std::min(t1, tb);
          hit = t0 <= t1;
        }
        if (hit && t0 > sensor.min_range_m && t0 < best) {
          best = t0;
          label = std::uint32_t(2 + k);
        }
      }
      if (d.z() < 0) {  // ground: march then bisect along the ray
        double lo = 0, hi = -1;
        for (double t = 0.2; t < best; t *= 1.02)
          if (t * d.z() <= ground_z(t * d.x(), t * d.y())) {
            hi = t;
            break;
          } else {
            lo = t;
          }
        if (hi > 0) {
          for (int it = 0; it < 40; ++it) {
            const double m = 0.5 * (lo + hi);
            (m * d.z() <= ground_z(m * d.x(), m * d.y()) ? hi : lo) = m;
          }
          if (hi < best && hi > sensor.min_range_m) {
            best = hi;
            label = 1;
          }
        }
      }
      if (label == 0) continue;
      const double r = best + noise(rng) * (noise_m > 0 ? 1.0 : 0.0);
      Point p;
      p.x = float(r * d.x());
      p.y = float(r * d.y());
      p.z = float(r * d.z());
      if (with_ring) p.ring = std::uint16_t(ring);
      cloud.push_back(p, label);
    }
  }
  cloud.width = std::uint32_t(cloud.size());
  return cloud;
}

/// A partition as sorted lists of sorted indices, for comparing clusterings regardless of order.
inline std::vector<std::vector<std::uint32_t>> canonical(
    std::vector<std::vector<std::uint32_t>> parts) {
  for (auto& p : parts) std::sort(p.begin(), p.end());
  std::sort(parts.begin(), parts.end());
  return parts;
}

}  // namespace fieldlidar::segmentation::test
