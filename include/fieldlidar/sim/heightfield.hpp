#pragma once
/// \file A regular grid of ground heights: the terrain of every scene, meshed exactly as it is
/// queried so that ground_height_at() and the ray-cast surface agree to float precision.

#include <functional>
#include <vector>

#include <Eigen/Core>

#include "fieldlidar/sim/mesh.hpp"

namespace fieldlidar::sim {

/// Heights (m, world z) at the nodes (i, j) located at origin + (i, j) * resolution. Each cell is
/// split along its (i,j)-(i+1,j+1) diagonal into two planar triangles.
class HeightField {
 public:
  HeightField() = default;
  /// Samples `height_of(x, y)` at every node of a grid covering [min, max].
  HeightField(const Eigen::Vector2d& min_m, const Eigen::Vector2d& max_m, double resolution_m,
              const std::function<double(double, double)>& height_of);

  /// Height of the meshed surface at (x, y); positions outside are clamped to the border.
  double height_at(const Eigen::Vector2d& xy_m) const;
  /// Upward unit normal of the triangle under (x, y).
  Eigen::Vector3d normal_at(const Eigen::Vector2d& xy_m) const;

  double resolution_m() const { return resolution_m_; }
  const Eigen::Vector2d& min_m() const { return origin_m_; }
  Eigen::Vector2d max_m() const;
  int nodes_x() const { return nx_; }
  int nodes_y() const { return ny_; }
  double node_height(int i, int j) const { return heights_[std::size_t(j) * nx_ + i]; }
  bool empty() const { return heights_.empty(); }

  /// The surface as triangles, all with `label`.
  TriangleMesh to_mesh(std::uint32_t label) const;

 private:
  Eigen::Vector2d origin_m_ = Eigen::Vector2d::Zero();
  double resolution_m_ = 1.0;
  int nx_ = 0, ny_ = 0;
  std::vector<float> heights_;
};

}  // namespace fieldlidar::sim
