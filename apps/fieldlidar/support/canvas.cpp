#include "support/canvas.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include <cairo.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/file_util.hpp"

namespace fieldlidar::app {

namespace {
cairo_status_t append_bytes(void* closure, const unsigned char* data, unsigned int length) {
  static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
  return CAIRO_STATUS_SUCCESS;
}
/// Encodes the PNG in memory, then writes it as every other output is written (io/file_util):
/// checked, complete or not at all.
void write_surface(cairo_surface_t* surface, const std::filesystem::path& path, bool overwrite) {
  io::check_writable(path, overwrite);
  std::string png;
  if (cairo_surface_write_to_png_stream(surface, append_bytes, &png) != CAIRO_STATUS_SUCCESS)
    throw Error(path.string() + ": cannot encode the PNG");
  io::write_file_atomic(path, png, overwrite);
}
}  // namespace

Rgb palette(std::uint32_t id) {
  if (id == 0) return {0.6, 0.6, 0.6};
  // Golden-ratio hue steps give neighbouring ids well separated colours.
  const double h = std::fmod(id * 0.618033988749895, 1.0) * 6.0;
  const double s = 0.75, v = 0.9;
  const int i = static_cast<int>(h);
  const double f = h - i, p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
  switch (i % 6) {
    case 0:
      return {v, t, p};
    case 1:
      return {q, v, p};
    case 2:
      return {p, v, t};
    case 3:
      return {p, q, v};
    case 4:
      return {t, p, v};
    default:
      return {v, p, q};
  }
}

Rgb ramp(double t) {
  if (!std::isfinite(t)) return {0.25, 0.25, 0.25};
  t = std::clamp(t, 0.0, 1.0);
  // Piecewise-linear approximation of viridis.
  static constexpr double k[5][3] = {{0.267, 0.005, 0.329},
                                     {0.230, 0.322, 0.546},
                                     {0.128, 0.567, 0.551},
                                     {0.369, 0.789, 0.383},
                                     {0.993, 0.906, 0.144}};
  const double x = t * 4.0;
  const int i = std::min(3, static_cast<int>(x));
  const double f = x - i;
  return {k[i][0] + f * (k[i + 1][0] - k[i][0]), k[i][1] + f * (k[i + 1][1] - k[i][1]),
          k[i][2] + f * (k[i + 1][2] - k[i][2])};
}

TopDownCanvas::TopDownCanvas(const Eigen::Vector2d& min_m, const Eigen::Vector2d& max_m,
                             int max_pixels)
    : min_m_(min_m) {
  Eigen::Vector2d extent = (max_m - min_m).cwiseMax(1e-3);
  if (!extent.allFinite()) throw Error("picture bounds are not finite");
  const int inner = std::max(100, max_pixels - 2 * margin_);
  scale_ = inner / extent.maxCoeff();
  width_ = static_cast<int>(std::ceil(extent.x() * scale_)) + 2 * margin_;
  height_ = static_cast<int>(std::ceil(extent.y() * scale_)) + 2 * margin_;
  surface_ = cairo_image_surface_create(CAIRO_FORMAT_RGB24, width_, height_);
  cr_ = cairo_create(surface_);
  cairo_set_source_rgb(cr_, 1, 1, 1);
  cairo_paint(cr_);
}

TopDownCanvas::~TopDownCanvas() {
  cairo_destroy(cr_);
  cairo_surface_destroy(surface_);
}

Eigen::Vector2d TopDownCanvas::to_pixel(const Eigen::Vector2d& w) const {
  return {margin_ + (w.x() - min_m_.x()) * scale_,
          height_ - margin_ - (w.y() - min_m_.y()) * scale_};
}

void TopDownCanvas::raster(const GridGeometry& g, std::span<const float> values, double lo,
                           double hi, double alpha) {
  const double span = hi > lo ? hi - lo : 1.0;
  const double cell = g.resolution_m * scale_;
  for (int iy = 0; iy < g.height; ++iy)
    for (int ix = 0; ix < g.width; ++ix) {
      const float v = values[g.linear_index(ix, iy)];
      if (!std::isfinite(v)) continue;
      const Rgb c = ramp((v - lo) / span);
      const Eigen::Vector2d p = to_pixel(g.origin_m + g.resolution_m * Eigen::Vector2d(ix, iy + 1));
      cairo_set_source_rgba(cr_, c.r, c.g, c.b, alpha);
      cairo_rectangle(cr_, p.x(), p.y(), cell + 0.5, cell + 0.5);
      cairo_fill(cr_);
    }
}

void TopDownCanvas::cell(const GridGeometry& g, int ix, int iy, const Rgb& c) {
  const double side = g.resolution_m * scale_;
  const Eigen::Vector2d p = to_pixel(g.origin_m + g.resolution_m * Eigen::Vector2d(ix, iy + 1));
  cairo_set_source_rgb(cr_, c.r, c.g, c.b);
  cairo_rectangle(cr_, p.x(), p.y(), side + 0.5, side + 0.5);
  cairo_fill(cr_);
}

void TopDownCanvas::dot(const Eigen::Vector2d& w, const Rgb& c, double radius_px) {
  const auto p = to_pixel(w);
  cairo_set_source_rgb(cr_, c.r, c.g, c.b);
  if (radius_px <= 1.0) {
    cairo_rectangle(cr_, p.x() - 0.5, p.y() - 0.5, 1.0, 1.0);
  } else {
    cairo_new_sub_path(cr_);
    cairo_arc(cr_, p.x(), p.y(), radius_px, 0, 2 * std::numbers::pi);
  }
  cairo_fill(cr_);
}

void TopDownCanvas::polyline(std::span<const Eigen::Vector2d> pts, const Rgb& c, double width_px,
                             bool closed) {
  if (pts.size() < 2) return;
  cairo_set_source_rgb(cr_, c.r, c.g, c.b);
  cairo_set_line_width(cr_, width_px);
  cairo_set_line_join(cr_, CAIRO_LINE_JOIN_ROUND);
  auto p = to_pixel(pts[0]);
  cairo_move_to(cr_, p.x(), p.y());
  for (std::size_t i = 1; i < pts.size(); ++i) {
    p = to_pixel(pts[i]);
    cairo_line_to(cr_, p.x(), p.y());
  }
  if (closed) cairo_close_path(cr_);
  cairo_stroke(cr_);
}

void TopDownCanvas::circle(const Eigen::Vector2d& center, double radius_m, const Rgb& c,
                           double width_px, bool fill) {
  const auto p = to_pixel(center);
  cairo_set_source_rgb(cr_, c.r, c.g, c.b);
  cairo_new_sub_path(cr_);
  cairo_arc(cr_, p.x(), p.y(), std::max(1.0, radius_m * scale_), 0, 2 * std::numbers::pi);
  if (fill) {
    cairo_fill(cr_);
  } else {
    cairo_set_line_width(cr_, width_px);
    cairo_stroke(cr_);
  }
}

void TopDownCanvas::arrow(const Eigen::Vector2d& from, double yaw, double length_m, const Rgb& c) {
  const Eigen::Vector2d dir(std::cos(yaw), std::sin(yaw));
  const Eigen::Vector2d tip = from + length_m * dir;
  const Eigen::Vector2d side(-dir.y(), dir.x());
  const Eigen::Vector2d pts[] = {from, tip, tip - 0.3 * length_m * dir + 0.15 * length_m * side,
                                 tip, tip - 0.3 * length_m * dir - 0.15 * length_m * side};
  polyline(pts, c, 2.0);
}

void TopDownCanvas::text(const Eigen::Vector2d& at, const std::string& s, const Rgb& c,
                         double size_px, bool pixel) {
  const auto p = pixel ? at : to_pixel(at);
  cairo_set_source_rgb(cr_, c.r, c.g, c.b);
  cairo_select_font_face(cr_, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr_, size_px);
  cairo_move_to(cr_, p.x(), p.y());
  cairo_show_text(cr_, s.c_str());
}

void TopDownCanvas::legend(const std::vector<std::pair<std::string, Rgb>>& entries) {
  const double x = margin_ + 8, y0 = margin_ + 8, row = 18;
  cairo_set_source_rgba(cr_, 1, 1, 1, 0.85);
  cairo_rectangle(cr_, x - 6, y0 - 6, 200, row * entries.size() + 8);
  cairo_fill(cr_);
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const auto& [label, c] = entries[i];
    cairo_set_source_rgb(cr_, c.r, c.g, c.b);
    cairo_rectangle(cr_, x, y0 + i * row, 12, 12);
    cairo_fill(cr_);
    text({x + 18, y0 + i * row + 11}, label, {}, 12.0, true);
  }
}

void TopDownCanvas::title(const std::string& s) {
  text({margin_, 20.0}, s, {}, 15.0, true);
}

void TopDownCanvas::save_png(const std::filesystem::path& path, bool overwrite) const {
  // Scale bar: the largest 1-2-5 step that fits in a fifth of the picture.
  const double target_m = width_ / 5.0 / scale_;
  double step = std::pow(10.0, std::floor(std::log10(target_m)));
  for (double m : {5.0, 2.0, 1.0})
    if (m * step <= target_m) {
      step *= m;
      break;
    }
  const double x0 = width_ - margin_ - step * scale_, y = height_ - 10.0;
  cairo_set_source_rgb(cr_, 0, 0, 0);
  cairo_set_line_width(cr_, 3);
  cairo_move_to(cr_, x0, y);
  cairo_line_to(cr_, x0 + step * scale_, y);
  cairo_stroke(cr_);
  cairo_set_font_size(cr_, 12);
  cairo_move_to(cr_, x0, y - 5);
  const std::string label =
      (step >= 1 ? std::to_string(static_cast<int>(step)) : std::to_string(step).substr(0, 4)) +
      " m";
  cairo_show_text(cr_, label.c_str());
  cairo_surface_flush(surface_);
  write_surface(surface_, path, overwrite);
}

RasterImage::RasterImage(int width, int height, const Rgb& bg) : width_(width), height_(height) {
  if (width <= 0 || height <= 0 || std::size_t(width) * height > (1u << 28))
    throw Error("image size " + std::to_string(width) + "x" + std::to_string(height) +
                " is not usable");
  argb_.assign(std::size_t(width) * height, 0);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) set(x, y, bg);
}

void RasterImage::set(int x, int y, const Rgb& c) {
  if (x < 0 || y < 0 || x >= width_ || y >= height_) return;
  auto to8 = [](double v) {
    return static_cast<std::uint32_t>(std::clamp(v, 0.0, 1.0) * 255.0 + 0.5);
  };
  argb_[std::size_t(y) * width_ + x] = (to8(c.r) << 16) | (to8(c.g) << 8) | to8(c.b);
}

void RasterImage::save_png(const std::filesystem::path& path, bool overwrite, int sx,
                           int sy) const {
  sx = std::max(1, sx);
  sy = std::max(1, sy);
  const int w = width_ * sx, h = height_ * sy;
  cairo_surface_t* s = cairo_image_surface_create(CAIRO_FORMAT_RGB24, w, h);
  const int stride = cairo_image_surface_get_stride(s);
  auto* data = cairo_image_surface_get_data(s);
  for (int y = 0; y < h; ++y) {
    auto* row = reinterpret_cast<std::uint32_t*>(data + std::size_t(y) * stride);
    for (int x = 0; x < w; ++x) row[x] = argb_[std::size_t(y / sy) * width_ + x / sx];
  }
  cairo_surface_mark_dirty(s);
  try {
    write_surface(s, path, overwrite);
  } catch (...) {
    cairo_surface_destroy(s);
    throw;
  }
  cairo_surface_destroy(s);
}

}  // namespace fieldlidar::app
