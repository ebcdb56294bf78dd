#include "fieldlidar/sim/heightfield.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace fieldlidar::sim {

HeightField::HeightField(const Eigen::Vector2d& min_m, const Eigen::Vector2d& max_m,
                         double resolution_m,
                         const std::function<double(double, double)>& height_of)
    : origin_m_(min_m), resolution_m_(resolution_m) {
  if (!(resolution_m > 0) || !(max_m.x() > min_m.x()) || !(max_m.y() > min_m.y()))
    throw std::invalid_argument("HeightField: need resolution_m > 0 and max > min");
  nx_ = static_cast<int>(std::ceil((max_m.x() - min_m.x()) / resolution_m)) + 1;
  ny_ = static_cast<int>(std::ceil((max_m.y() - min_m.y()) / resolution_m)) + 1;
  heights_.resize(std::size_t(nx_) * ny_);
  for (int j = 0; j < ny_; ++j)
    for (int i = 0; i < nx_; ++i)
      heights_[std::size_t(j) * nx_ + i] = static_cast<float>(
          height_of(origin_m_.x() + i * resolution_m_, origin_m_.y() + j * resolution_m_));
}

Eigen::Vector2d HeightField::max_m() const {
  return origin_m_ + resolution_m_ * Eigen::Vector2d(nx_ - 1, ny_ - 1);
}

namespace {
struct CellPos {
  int i, j;
  double fx, fy;
};
CellPos locate(const Eigen::Vector2d& xy, const Eigen::Vector2d& origin, double res, int nx,
               int ny) {
  const double gx = std::clamp((xy.x() - origin.x()) / res, 0.0, double(nx - 1));
  const double gy = std::clamp((xy.y() - origin.y()) / res, 0.0, double(ny - 1));
  const int i = std::min(static_cast<int>(gx), nx - 2);
  const int j = std::min(static_cast<int>(gy), ny - 2);
  return {i, j, gx - i, gy - j};
}
}  // namespace

double HeightField::height_at(const Eigen::Vector2d& xy_m) const {
  if (heights_.empty()) return 0.0;
  const auto c = locate(xy_m, origin_m_, resolution_m_, nx_, ny_);
  const double h00 = node_height(c.i, c.j), h10 = node_height(c.i + 1, c.j);
  const double h01 = node_height(c.i, c.j + 1), h11 = node_height(c.i + 1, c.j + 1);
  // Same split as to_mesh(): triangle (00, 10, 11) when fx >= fy, else (00, 11, 01).
  if (c.fx >= c.fy) return h00 + c.fx * (h10 - h00) + c.fy * (h11 - h10);
  return h00 + c.fy * (h01 - h00) + c.fx * (h11 - h01);
}

Eigen::Vector3d HeightField::normal_at(const Eigen::Vector2d& xy_m) const {
  if (heights_.empty()) return Eigen::Vector3d::UnitZ();
  const auto c = locate(xy_m, origin_m_, resolution_m_, nx_, ny_);
  const double h00 = node_height(c.i, c.j), h10 = node_height(c.i + 1, c.j);
  const double h01 = node_height(c.i, c.j + 1), h11 = node_height(c.i + 1, c.j + 1);
  double dzdx, dzdy;
  if (c.fx >= c.fy) {
    dzdx = (h10 - h00) / resolution_m_;
    dzdy = (h11 - h10) / resolution_m_;
  } else {
    dzdy = (h01 - h00) / resolution_m_;
    dzdx = (h11 - h01) / resolution_m_;
  }
  return Eigen::Vector3d(-dzdx, -dzdy, 1.0).normalized();
}

TriangleMesh HeightField::to_mesh(std::uint32_t label) const {
  TriangleMesh m;
  m.vertices.reserve(heights_.size());
  for (int j = 0; j < ny_; ++j)
    for (int i = 0; i < nx_; ++i)
      m.vertices.emplace_back(float(origin_m_.x() + i * resolution_m_),
                              float(origin_m_.y() + j * resolution_m_), node_height(i, j));
  m.triangles.reserve(std::size_t(nx_ - 1) * (ny_ - 1) * 2);
  for (int j = 0; j + 1 < ny_; ++j)
    for (int i = 0; i + 1 < nx_; ++i) {
      const auto v00 = std::uint32_t(j * nx_ + i), v10 = v00 + 1;
      const auto v01 = std::uint32_t((j + 1) * nx_ + i), v11 = v01 + 1;
      m.triangles.push_back({v00, v10, v11});
      m.triangles.push_back({v00, v11, v01});
    }
  m.labels.assign(m.triangles.size(), label);
  return m;
}

}  // namespace fieldlidar::sim
