#pragma once
// Scoring a traversability map per cell against the simulated scene's terrain truth, on the cells
// the map claims to know (impassable is the positive class).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>

#include "fieldlidar/core/grid2d.hpp"
#include "fieldlidar/core/pose.hpp"
#include "fieldlidar/terrain/traversability.hpp"

namespace fieldlidar::terrain::test {

struct Score {
  int tp = 0, fp = 0, fn = 0, tn = 0;
  int known = 0, truth_cells = 0;
  double slope_sq = 0, agreed_sq = 0;
  int slope_n = 0, agreed_n = 0;
  double impassable_recall() const { return tp / double(std::max(1, tp + fn)); }
  double impassable_precision() const { return tp / double(std::max(1, tp + fp)); }
  double passable_precision() const { return tn / double(std::max(1, tn + fn)); }
  double passable_recall() const { return tn / double(std::max(1, tn + fp)); }
  double impassable_f1() const {
    const double p = impassable_precision(), r = impassable_recall();
    return p + r > 0 ? 2 * p * r / (p + r) : 0.0;
  }
  double accuracy() const { return (tp + tn) / double(std::max(1, known)); }
  double coverage() const { return known / double(std::max(1, truth_cells)); }
  double slope_rmse() const { return std::sqrt(slope_sq / std::max(1, slope_n)); }
  /// On the cells both the truth and the map call passable.
  double slope_rmse_agreed() const { return std::sqrt(agreed_sq / std::max(1, agreed_n)); }
};

/// Adds the truth cells for which `keep(centre)` holds to the score. With `T_map_world`, the map
/// is in another frame (e.g. the first scan's): each truth cell's centre on the ground (its
/// elevation) is looked up where that frame puts it.
inline void score(const Grid2D& map, const Grid2D& truth,
                  const std::function<bool(const Eigen::Vector2d&)>& keep, Score& s,
                  const Pose* T_map_world = nullptr) {
  const auto& g = truth.geometry();
  for (int iy = 0; iy < g.height; ++iy)
    for (int ix = 0; ix < g.width; ++ix) {
      const Eigen::Vector2d w = g.cell_center(ix, iy);
      if (!keep(w)) continue;
      ++s.truth_cells;
      const Eigen::Vector2d c =
          T_map_world
              ? Eigen::Vector2d(
                    (*T_map_world * Eigen::Vector3d(w.x(), w.y(), truth.at("elevation", ix, iy)))
                        .head<2>())
              : w;
      const auto v = map.value_at(layer::kImpassable, c);
      if (!v || std::isnan(*v)) continue;
      ++s.known;
      const bool ours = *v > 0.5f, theirs = truth.at("passable", ix, iy) < 0.5f;
      s.tp += ours && theirs;
      s.fp += ours && !theirs;
      s.fn += !ours && theirs;
      s.tn += !ours && !theirs;
      const float sl = *map.value_at(layer::kSlopeDeg, c);
      if (!theirs && std::isfinite(sl)) {
        const double e2 = std::pow(sl - truth.at("slope_deg", ix, iy), 2);
        s.slope_sq += e2;
        ++s.slope_n;
        if (!ours) s.agreed_sq += e2, ++s.agreed_n;
      }
    }
}

inline void print(const char* name, const Score& s) {
  std::printf(
      "%s: impassable recall %.3f precision %.3f F1 %.3f, passable precision %.3f recall %.3f, "
      "accuracy %.3f, coverage %.3f (%d known), slope RMSE on passable %.2f deg (on cells both "
      "call passable %.2f deg)\n",
      name, s.impassable_recall(), s.impassable_precision(), s.impassable_f1(),
      s.passable_precision(), s.passable_recall(), s.accuracy(), s.coverage(), s.known,
      s.slope_rmse(), s.slope_rmse_agreed());
}

}  // namespace fieldlidar::terrain::test
