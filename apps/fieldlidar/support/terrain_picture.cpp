// Four panels side by side on one canvas, each the map's grid shifted in the picture's frame.
#include "support/terrain_picture.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include <fmt/core.h>

#include "support/canvas.hpp"

namespace fieldlidar::app {
namespace {

const Rgb kUnknown{0.6, 0.6, 0.6};
const Rgb kBlocked{0, 0, 0};

// tau 0 red, 1 green.
Rgb tau_colour(double tau) {
  const double t = std::clamp(tau, 0.0, 1.0);
  return {std::min(1.0, 2.0 * (1.0 - t)), std::min(1.0, 2.0 * t), 0.1};
}

/// Why a cell blocks: too steep (orange), a step or pit (purple), an obstacle (black).
Rgb reason_colour(float steep, float step, float obstacle, float impassable, double max_step_m) {
  if (!std::isfinite(impassable)) return kUnknown;
  if (impassable < 0.5f) return {1, 1, 1};
  if (obstacle > 0.5f) return kBlocked;
  if (steep > 0.5f) return {1.0, 0.55, 0.0};
  if (std::isfinite(step) && step > max_step_m) return {0.55, 0.2, 0.7};
  return kBlocked;
}

}  // namespace

void draw_terrain_map(const Grid2D& map, const terrain::RobotConfig& robot,
                      const std::string& title, const std::filesystem::path& path, bool force) {
  namespace L = terrain::layer;
  const GridGeometry& g = map.geometry();
  const Eigen::Vector2d size(g.width * g.resolution_m, g.height * g.resolution_m);
  const double gap = 0.06 * std::max(size.x(), size.y());
  // Panels in a 2 x 2 block: (0,1) top-left ... (1,0) bottom-right.
  const std::array<Eigen::Vector2d, 4> shift = {
      Eigen::Vector2d(0, size.y() + gap), Eigen::Vector2d(size.x() + gap, size.y() + gap),
      Eigen::Vector2d(0, 0), Eigen::Vector2d(size.x() + gap, 0)};
  TopDownCanvas canvas(g.origin_m, g.origin_m + 2 * size + Eigen::Vector2d(gap, 2.4 * gap), 1400);
  const auto tau = map.layer(L::kTraversability), impassable = map.layer(L::kImpassable);
  const auto slope = map.layer(L::kSlopeDeg), rough = map.layer(L::kRoughness);
  const auto steep = map.layer(L::kObstacle2d), step = map.layer(L::kStep);
  const auto obstacle = map.layer(L::kObstacleProjected);
  const double rough_top = robot.max_step_m / 2;
  for (int iy = 0; iy < g.height; ++iy)
    for (int ix = 0; ix < g.width; ++ix) {
      const std::size_t i = g.linear_index(ix, iy);
      const bool known = std::isfinite(impassable[i]);
      const bool blocked = known && impassable[i] > 0.5f;
      std::array<Rgb, 4> c;
      c[0] = !known ? kUnknown : blocked ? kBlocked : tau_colour(tau[i]);
      c[1] = std::isfinite(slope[i]) ? ramp(slope[i] / robot.max_slope_deg) : kUnknown;
      if (std::isfinite(slope[i]) && slope[i] > robot.max_slope_deg) c[1] = {0.8, 0.0, 0.0};
      c[2] = std::isfinite(rough[i]) ? ramp(rough[i] / rough_top) : kUnknown;
      c[3] = reason_colour(steep[i], step[i], obstacle[i], impassable[i], robot.max_step_m);
      for (int k = 0; k < 4; ++k) {
        GridGeometry shifted = g;
        shifted.origin_m += shift[std::size_t(k)];
        canvas.cell(shifted, ix, iy, c[std::size_t(k)]);
      }
    }
  const std::array<std::string, 4> names = {
      "traversability tau (green 1, red 0)",
      fmt::format("slope: 0 (blue) .. {:g} deg (yellow), red steeper", robot.max_slope_deg),
      fmt::format("roughness: 0 (blue) .. {:g} m (yellow)", rough_top),
      "impassable: obstacle, too steep, step/pit"};
  for (int k = 0; k < 4; ++k)
    canvas.text(g.origin_m + shift[std::size_t(k)] + Eigen::Vector2d(0, size.y() + 0.2 * gap),
                names[std::size_t(k)], {}, 14.0);
  canvas.title(title);
  // The legend as one coloured line above the panels.
  const std::array<std::pair<const char*, Rgb>, 5> legend = {{{"impassable / obstacle", kBlocked},
                                                              {"too steep", {1.0, 0.55, 0.0}},
                                                              {"step or pit", {0.55, 0.2, 0.7}},
                                                              {"tau 0.5", tau_colour(0.5)},
                                                              {"unknown (never free)", kUnknown}}};
  Eigen::Vector2d at = g.origin_m + Eigen::Vector2d(0, 2 * size.y() + 1.9 * gap);
  for (const auto& [label, colour] : legend) {
    canvas.text(at, std::string("\u25A0 ") + label, colour, 14.0);
    at.x() += (2 * size.x() + gap) / 5.0;
  }
  canvas.save_png(path, force);
}

}  // namespace fieldlidar::app
