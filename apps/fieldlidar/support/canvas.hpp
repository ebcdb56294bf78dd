#pragma once
// PNG pictures for the CLI (cairo): top-down world views and plain raster images.

#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "fieldlidar/core/grid2d.hpp"

typedef struct _cairo cairo_t;
typedef struct _cairo_surface cairo_surface_t;

namespace fieldlidar::app {

struct Rgb {
  double r = 0, g = 0, b = 0;  ///< 0..1
};

/// A distinct colour per id (clusters, tracks, trunks); id 0 is grey.
Rgb palette(std::uint32_t id);
/// Perceptual blue-green-yellow ramp for t in [0, 1] (clamped); NaN gives dark grey.
Rgb ramp(double t);

/// A top-down view of a world rectangle (x right, y up), scaled to fit `max_pixels` on its long
/// side with a margin, white background, a metric scale bar drawn on save.
class TopDownCanvas {
 public:
  TopDownCanvas(const Eigen::Vector2d& min_m, const Eigen::Vector2d& max_m, int max_pixels = 1200);
  ~TopDownCanvas();
  TopDownCanvas(const TopDownCanvas&) = delete;
  TopDownCanvas& operator=(const TopDownCanvas&) = delete;

  Eigen::Vector2d to_pixel(const Eigen::Vector2d& world_m) const;
  double pixels_per_metre() const { return scale_; }

  /// Colours each cell of a grid layer by `ramp((v - lo) / (hi - lo))`; NaN cells are skipped.
  void raster(const GridGeometry& geometry, std::span<const float> values, double lo, double hi,
              double alpha = 1.0);
  /// Fills cell (ix, iy) of a grid with one colour.
  void cell(const GridGeometry& geometry, int ix, int iy, const Rgb& color);
  void dot(const Eigen::Vector2d& world_m, const Rgb& color, double radius_px = 1.0);
  void polyline(std::span<const Eigen::Vector2d> world_m, const Rgb& color, double width_px = 2.0,
                bool closed = false);
  void circle(const Eigen::Vector2d& center_m, double radius_m, const Rgb& color,
              double width_px = 1.5, bool fill = false);
  void arrow(const Eigen::Vector2d& from_m, double yaw_rad, double length_m, const Rgb& color);
  /// Text at a world position (or, with `pixel` true, at pixel coordinates).
  void text(const Eigen::Vector2d& at, const std::string& s, const Rgb& color = {},
            double size_px = 13.0, bool pixel = false);
  /// A legend box in the top-left corner.
  void legend(const std::vector<std::pair<std::string, Rgb>>& entries);
  void title(const std::string& s);
  /// Writes the PNG; refuses to replace an existing file unless `overwrite`.
  void save_png(const std::filesystem::path& path, bool overwrite) const;

 private:
  Eigen::Vector2d min_m_;
  double scale_ = 1.0;
  int width_ = 0, height_ = 0, margin_ = 30;
  cairo_surface_t* surface_ = nullptr;
  cairo_t* cr_ = nullptr;
};

/// A plain RGB raster (e.g. a range image), saved as PNG.
class RasterImage {
 public:
  RasterImage(int width, int height, const Rgb& background = {1, 1, 1});
  void set(int x, int y, const Rgb& color);
  int width() const { return width_; }
  int height() const { return height_; }
  /// Writes the PNG scaled by integer factors (sx, sy) so thin images stay visible.
  void save_png(const std::filesystem::path& path, bool overwrite, int sx = 1, int sy = 1) const;

 private:
  int width_, height_;
  std::vector<std::uint32_t> argb_;
};

}  // namespace fieldlidar::app
