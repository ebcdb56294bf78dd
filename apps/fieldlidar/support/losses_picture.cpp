#include "support/losses_picture.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include <fmt/core.h>

#include "support/canvas.hpp"

namespace fieldlidar::app {

namespace {

/// One colour per step of the pipeline, from grey (never seen) through warm (lost early) to
/// green (reported).
Rgb loss_colour(people::PersonLoss loss) {
  static const std::array<Rgb, people::kPersonLosses> colours{{
      {0.55, 0.55, 0.55},  // no segment
      {0.85, 0.1, 0.1},    // not a candidate
      {0.6, 0.35, 0.2},    // not foreground
      {0.45, 0.3, 0.6},    // background
      {0.95, 0.5, 0.1},    // not a leg
      {0.55, 0.2, 0.7},    // occupied
      {0.9, 0.75, 0.1},    // no person track
      {0.2, 0.55, 0.95},   // not reported
      {0.1, 0.75, 0.75},   // reported beyond the gate
      {0.1, 0.6, 0.15},    // reported
  }};
  return colours[std::size_t(loss)];
}

}  // namespace

void write_losses_picture(const std::filesystem::path& path, std::span<const PlacedLoss> persons,
                          const std::vector<double>& wedge_deg, const std::string& title,
                          bool overwrite) {
  double reach = 3.0;  // m, at least
  for (const auto& p : persons) reach = std::max(reach, p.position_m.norm());
  reach = std::ceil(reach + 0.5);
  TopDownCanvas canvas({-reach, -reach}, {reach, reach}, 1000);
  for (int r = 1; r <= int(reach); ++r) canvas.circle({0, 0}, r, {0.85, 0.85, 0.85}, 1.0);
  if (wedge_deg.size() == 2)
    for (const double a : wedge_deg) {
      const double rad = a * std::numbers::pi / 180.0;
      const std::vector<Eigen::Vector2d> ray{{0, 0},
                                             reach * Eigen::Vector2d(std::cos(rad), std::sin(rad))};
      canvas.polyline(ray, {0.4, 0.4, 0.4}, 1.0);
    }
  canvas.arrow({0, 0}, 0.0, 0.8, {0, 0, 0});
  people::PersonLossCounts counts{};
  for (const auto& p : persons) ++counts[std::size_t(p.loss)];
  for (const auto& p : persons) canvas.dot(p.position_m, loss_colour(p.loss), 3.0);
  std::vector<std::pair<std::string, Rgb>> legend;
  for (std::size_t k = 0; k < people::kPersonLosses; ++k) {
    const auto loss = people::PersonLoss(k);
    legend.emplace_back(fmt::format("{} ({})", people::person_loss_name(loss), counts[k]),
                        loss_colour(loss));
  }
  legend.emplace_back("range rings: 1 m; arrow: sensor x", Rgb{0.6, 0.6, 0.6});
  canvas.legend(legend);
  canvas.title(title);
  canvas.save_png(path, overwrite);
}

}  // namespace fieldlidar::app
