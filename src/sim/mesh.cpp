#include "fieldlidar/sim/mesh.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace fieldlidar::sim {

void TriangleMesh::append(const TriangleMesh& other) {
  const auto base = static_cast<std::uint32_t>(vertices.size());
  vertices.insert(vertices.end(), other.vertices.begin(), other.vertices.end());
  for (const auto& t : other.triangles)
    triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  labels.insert(labels.end(), other.labels.begin(), other.labels.end());
}

void TriangleMesh::add_triangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                const Eigen::Vector3d& c, std::uint32_t label) {
  const auto base = static_cast<std::uint32_t>(vertices.size());
  vertices.push_back(a.cast<float>());
  vertices.push_back(b.cast<float>());
  vertices.push_back(c.cast<float>());
  triangles.push_back({base, base + 1, base + 2});
  labels.push_back(label);
}

TriangleMesh make_box(const Pose& T_world_box, const Eigen::Vector3d& size_m, std::uint32_t label) {
  TriangleMesh m;
  const Eigen::Vector3d h = size_m / 2;
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d corner((i & 1) ? h.x() : -h.x(), (i & 2) ? h.y() : -h.y(),
                                 (i & 4) ? h.z() : -h.z());
    m.vertices.push_back((T_world_box * corner).cast<float>());
  }
  // Faces as quads (outward counter-clockwise), two triangles each.
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.triangles.push_back({std::uint32_t(q[0]), std::uint32_t(q[1]), std::uint32_t(q[2])});
    m.triangles.push_back({std::uint32_t(q[0]), std::uint32_t(q[2]), std::uint32_t(q[3])});
  }
  m.labels.assign(m.triangles.size(), label);
  return m;
}

TriangleMesh make_aabb(const Eigen::Vector3d& min_m, const Eigen::Vector3d& max_m,
                       std::uint32_t label) {
  Pose T = Pose::Identity();
  T.translation() = (min_m + max_m) / 2;
  return make_box(T, (max_m - min_m).cwiseAbs(), label);
}

TriangleMesh make_cylinder(const Eigen::Vector3d& base_m, const Eigen::Vector3d& top_m,
                           double base_radius_m, double top_radius_m, int segments,
                           std::uint32_t label, bool caps) {
  TriangleMesh m;
  segments = std::max(segments, 3);
  const Eigen::Vector3d axis = (top_m - base_m).normalized();
  // Any unit vector orthogonal to the axis, then the third by cross product.
  Eigen::Vector3d u = std::abs(axis.z()) < 0.9 ? axis.cross(Eigen::Vector3d::UnitZ())
                                               : axis.cross(Eigen::Vector3d::UnitX());
  u.normalize();
  const Eigen::Vector3d v = axis.cross(u);
  for (int i = 0; i < segments; ++i) {
    const double a = 2 * std::numbers::pi * i / segments;
    const Eigen::Vector3d r = std::cos(a) * u + std::sin(a) * v;
    m.vertices.push_back((base_m + base_radius_m * r).cast<float>());
    m.vertices.push_back((top_m + top_radius_m * r).cast<float>());
  }
  const auto n = static_cast<std::uint32_t>(segments);
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t j = (i + 1) % n;
    m.triangles.push_back({2 * i, 2 * j, 2 * j + 1});
    m.triangles.push_back({2 * i, 2 * j + 1, 2 * i + 1});
  }
  if (caps) {
    const auto cb = static_cast<std::uint32_t>(m.vertices.size());
    m.vertices.push_back(base_m.cast<float>());
    m.vertices.push_back(top_m.cast<float>());
    for (std::uint32_t i = 0; i < n; ++i) {
      const std::uint32_t j = (i + 1) % n;
      m.triangles.push_back({cb, 2 * j, 2 * i});
      m.triangles.push_back({cb + 1, 2 * i + 1, 2 * j + 1});
    }
  }
  m.labels.assign(m.triangles.size(), label);
  return m;
}

TriangleMesh make_blob(const Eigen::Vector3d& center_m, const Eigen::Vector3d& radii_m,
                       double roughness, std::mt19937_64& rng, std::uint32_t label, int rings,
                       int sectors) {
  TriangleMesh m;
  rings = std::max(rings, 3);
  sectors = std::max(sectors, 4);
  std::uniform_real_distribution<double> jitter(1.0 - roughness, 1.0 + roughness);
  const auto vertex = [&](double theta, double phi) {
    const Eigen::Vector3d d(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                            std::cos(theta));
    return Eigen::Vector3d(center_m + jitter(rng) * radii_m.cwiseProduct(d));
  };
  m.vertices.push_back(vertex(0, 0).cast<float>());  // north pole
  for (int r = 1; r < rings; ++r)
    for (int s = 0; s < sectors; ++s)
      m.vertices.push_back(
          vertex(std::numbers::pi * r / rings, 2 * std::numbers::pi * s / sectors).cast<float>());
  m.vertices.push_back(vertex(std::numbers::pi, 0).cast<float>());  // south pole
  const auto idx = [&](int r, int s) {
    return static_cast<std::uint32_t>(1 + (r - 1) * sectors + (s % sectors));
  };
  const auto south = static_cast<std::uint32_t>(m.vertices.size() - 1);
  for (int s = 0; s < sectors; ++s) {
    m.triangles.push_back({0, idx(1, s), idx(1, s + 1)});
    m.triangles.push_back({south, idx(rings - 1, s + 1), idx(rings - 1, s)});
    for (int r = 1; r + 1 < rings; ++r) {
      m.triangles.push_back({idx(r, s), idx(r + 1, s), idx(r + 1, s + 1)});
      m.triangles.push_back({idx(r, s), idx(r + 1, s + 1), idx(r, s + 1)});
    }
  }
  m.labels.assign(m.triangles.size(), label);
  return m;
}

}  // namespace fieldlidar::sim
