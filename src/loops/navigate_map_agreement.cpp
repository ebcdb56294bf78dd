// The built map against the truth near a drive: the cells it blocked that the truth lets a robot
// cross, and the cells it let the planner use that the truth does not.

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/loops/navigate_maps.hpp"
#include "fieldlidar/planning/planning_map.hpp"

namespace fieldlidar::loops {

MapAgreement map_agreement(const Grid2D& built, const Grid2D& truth,
                           std::span<const planning::Pose2> driven, double radius_m) {
  namespace L = terrain::layer;
  const GridGeometry& g = built.geometry();
  const GridGeometry& t = truth.geometry();
  if (g.width != t.width || g.height != t.height || g.resolution_m != t.resolution_m ||
      g.origin_m != t.origin_m)
    throw Error("map agreement: the built map and the truth lie on different grids");
  for (const char* layer : {L::kTraversability, L::kImpassable})
    if (!built.has_layer(layer))
      throw Error(std::string("map agreement: the built map has no layer '") + layer + "'");
  if (!truth.has_layer("passable")) throw Error("map agreement: the truth has no layer 'passable'");
  if (!(radius_m >= 0.0 && std::isfinite(radius_m)))
    throw Error("map agreement: radius_m " + std::to_string(radius_m));
  MapAgreement out;
  out.radius_m = radius_m;
  // The cells near the drive: a disc of cells round each pose's cell.
  std::vector<std::uint8_t> near(g.cell_count(), 0);
  const int reach = int(std::ceil(radius_m / g.resolution_m));
  std::optional<Eigen::Vector2i> last;  // poses 0.1 s apart share cells: one disc per cell run
  for (const auto& p : driven) {
    const auto c = g.cell_of({p.x_m, p.y_m});
    if (!c || c == last) continue;
    last = c;
    for (int dy = -reach; dy <= reach; ++dy)
      for (int dx = -reach; dx <= reach; ++dx)
        if (g.contains(c->x() + dx, c->y() + dy) && std::hypot(dx, dy) * g.resolution_m <= radius_m)
          near[g.linear_index(c->x() + dx, c->y() + dy)] = 1;
  }
  const auto tau = built.layer(L::kTraversability), imp = built.layer(L::kImpassable);
  const bool has_points = built.has_layer(L::kPoints);
  const auto points = has_points ? built.layer(L::kPoints) : decltype(tau){};
  const auto passable = truth.layer("passable");
  const auto truth_blocked = [&](int x, int y) {
    return g.contains(x, y) && passable[g.linear_index(x, y)] < 0.5f;
  };
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      const std::size_t i = g.linear_index(x, y);
      if (!near[i]) continue;
      const planning::CellRead read =
          planning::read_cell(tau[i], imp[i], has_points ? points[i] : 1.0f);
      if (read == planning::CellRead::kUnknown) continue;
      ++out.known_cells;
      const bool free_in_truth = passable[i] >= 0.5f;
      out.truth_passable += free_in_truth;
      if (free_in_truth && read == planning::CellRead::kBlocked) {
        ++out.passable_blocked;
        bool beside = false;
        for (int dy = -1; dy <= 1 && !beside; ++dy)
          for (int dx = -1; dx <= 1 && !beside; ++dx) beside = truth_blocked(x + dx, y + dy);
        out.passable_blocked_beside_impassable += beside;
      } else if (!free_in_truth && read == planning::CellRead::kPassable) {
        ++out.impassable_passable;
      }
    }
  return out;
}

}  // namespace fieldlidar::loops
