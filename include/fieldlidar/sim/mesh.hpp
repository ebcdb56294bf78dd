#pragma once
/// \file Triangle meshes of the static scene (ground, buildings, trunks, ...) with a label per
/// triangle, and the small builders the procedural scenes are made of.

#include <array>
#include <cstdint>
#include <random>
#include <vector>

#include <Eigen/Core>

#include "fieldlidar/core/pose.hpp"

namespace fieldlidar::sim {

/// Triangles in the world frame (m), counter-clockwise seen from outside, one label per triangle
/// (core/labels.hpp layout: class in the low 16 bits, instance id in the high 16 bits).
struct TriangleMesh {
  std::vector<Eigen::Vector3f> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::vector<std::uint32_t> labels;  ///< one per triangle

  std::size_t size() const { return triangles.size(); }
  bool empty() const { return triangles.empty(); }
  void append(const TriangleMesh& other);
  /// Adds one triangle from three new vertices.
  void add_triangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                    std::uint32_t label);
};

/// A box of size (x, y, z) m centred on the origin of `T_world_box`.
TriangleMesh make_box(const Pose& T_world_box, const Eigen::Vector3d& size_m, std::uint32_t label);

/// An axis-aligned box between two corners (m).
TriangleMesh make_aabb(const Eigen::Vector3d& min_m, const Eigen::Vector3d& max_m,
                       std::uint32_t label);

/// A (possibly tapered) cylinder from `base_m` to `top_m` with `segments` facets around; the
/// facets' vertices lie on the true circle. `caps` closes both ends.
TriangleMesh make_cylinder(const Eigen::Vector3d& base_m, const Eigen::Vector3d& top_m,
                           double base_radius_m, double top_radius_m, int segments,
                           std::uint32_t label, bool caps = true);

/// An ellipsoid blob (shrub, rock, crown, plant) with radii (m); each vertex is pushed in or out
/// radially by up to `roughness` (fraction of the radius) drawn from `rng`.
TriangleMesh make_blob(const Eigen::Vector3d& center_m, const Eigen::Vector3d& radii_m,
                       double roughness, std::mt19937_64& rng, std::uint32_t label, int rings = 8,
                       int sectors = 12);

}  // namespace fieldlidar::sim
