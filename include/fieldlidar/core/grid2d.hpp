#pragma once
/// \file A 2D grid of named float layers (elevation, slope, roughness, traversability, ...).

#include <cstddef>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace fieldlidar {

/// Placement of a grid in the world x-y plane. Cell (ix, iy) covers
/// [origin.x + ix*res, origin.x + (ix+1)*res) x [origin.y + iy*res, origin.y + (iy+1)*res).
struct GridGeometry {
  double resolution_m = 0.1;
  Eigen::Vector2d origin_m = Eigen::Vector2d::Zero();  ///< world position of cell (0,0)'s corner
  int width = 0;                                       ///< cells along x
  int height = 0;                                      ///< cells along y

  std::size_t cell_count() const { return std::size_t(width) * std::size_t(height); }
  /// Cell containing a world point, nullopt when outside.
  std::optional<Eigen::Vector2i> cell_of(const Eigen::Vector2d& world_m) const;
  Eigen::Vector2d cell_center(int ix, int iy) const;
  std::size_t linear_index(int ix, int iy) const { return std::size_t(iy) * width + ix; }
  bool contains(int ix, int iy) const { return ix >= 0 && iy >= 0 && ix < width && iy < height; }
  /// Grid of the given resolution that covers [min, max].
  static GridGeometry covering(const Eigen::Vector2d& min_m, const Eigen::Vector2d& max_m,
                               double resolution_m);
};

/// Named float layers over one GridGeometry, each stored row-major (index = iy * width + ix).
/// NaN marks "unknown".
class Grid2D {
 public:
  Grid2D() = default;
  explicit Grid2D(GridGeometry geometry);

  const GridGeometry& geometry() const { return geometry_; }
  /// Adds (or resets) a layer filled with `value`.
  std::span<float> add_layer(const std::string& name, float value);
  bool has_layer(const std::string& name) const { return layers_.count(name) != 0; }
  /// Throws std::out_of_range naming the layer when it does not exist.
  std::span<float> layer(const std::string& name);
  std::span<const float> layer(const std::string& name) const;
  std::vector<std::string> layer_names() const;

  float& at(const std::string& name, int ix, int iy);
  float at(const std::string& name, int ix, int iy) const;
  /// Value at a world point, nullopt when outside the grid.
  std::optional<float> value_at(const std::string& name, const Eigen::Vector2d& world_m) const;

 private:
  GridGeometry geometry_;
  std::map<std::string, std::vector<float>> layers_;
};

}  // namespace fieldlidar
