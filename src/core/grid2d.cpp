#include "fieldlidar/core/grid2d.hpp"

#include <cmath>
#include <stdexcept>

namespace fieldlidar {

std::optional<Eigen::Vector2i> GridGeometry::cell_of(const Eigen::Vector2d& world_m) const {
  const Eigen::Vector2d rel = (world_m - origin_m) / resolution_m;
  if (!std::isfinite(rel.x()) || !std::isfinite(rel.y())) return std::nullopt;
  const int ix = static_cast<int>(std::floor(rel.x()));
  const int iy = static_cast<int>(std::floor(rel.y()));
  if (!contains(ix, iy)) return std::nullopt;
  return Eigen::Vector2i(ix, iy);
}

Eigen::Vector2d GridGeometry::cell_center(int ix, int iy) const {
  return origin_m + resolution_m * Eigen::Vector2d(ix + 0.5, iy + 0.5);
}

GridGeometry GridGeometry::covering(const Eigen::Vector2d& min_m, const Eigen::Vector2d& max_m,
                                    double resolution_m) {
  if (!(resolution_m > 0) || !std::isfinite(resolution_m))
    throw std::invalid_argument("grid resolution_m must be > 0");
  if (!min_m.allFinite() || !max_m.allFinite() || (max_m - min_m).minCoeff() < 0)
    throw std::invalid_argument("grid bounds must be finite with max >= min");
  GridGeometry g;
  g.resolution_m = resolution_m;
  g.origin_m = min_m;
  const Eigen::Vector2d cells = ((max_m - min_m) / resolution_m).array().floor() + 1.0;
  if (cells.x() * cells.y() > 1e9) throw std::invalid_argument("grid would exceed 1e9 cells");
  g.width = static_cast<int>(cells.x());
  g.height = static_cast<int>(cells.y());
  return g;
}

Grid2D::Grid2D(GridGeometry geometry) : geometry_(geometry) {
  if (geometry.width < 0 || geometry.height < 0 || !(geometry.resolution_m > 0))
    throw std::invalid_argument("Grid2D: need width, height >= 0 and resolution_m > 0");
}

std::span<float> Grid2D::add_layer(const std::string& name, float value) {
  auto& data = layers_[name];
  data.assign(geometry_.cell_count(), value);
  return data;
}

std::span<float> Grid2D::layer(const std::string& name) {
  auto it = layers_.find(name);
  if (it == layers_.end()) throw std::out_of_range("Grid2D has no layer '" + name + "'");
  return it->second;
}

std::span<const float> Grid2D::layer(const std::string& name) const {
  auto it = layers_.find(name);
  if (it == layers_.end()) throw std::out_of_range("Grid2D has no layer '" + name + "'");
  return it->second;
}

std::vector<std::string> Grid2D::layer_names() const {
  std::vector<std::string> names;
  for (const auto& [name, data] : layers_) names.push_back(name);
  return names;
}

float& Grid2D::at(const std::string& name, int ix, int iy) {
  return layer(name)[geometry_.linear_index(ix, iy)];
}

float Grid2D::at(const std::string& name, int ix, int iy) const {
  return layer(name)[geometry_.linear_index(ix, iy)];
}

std::optional<float> Grid2D::value_at(const std::string& name,
                                      const Eigen::Vector2d& world_m) const {
  const auto cell = geometry_.cell_of(world_m);
  if (!cell) return std::nullopt;
  return at(name, cell->x(), cell->y());
}

}  // namespace fieldlidar
