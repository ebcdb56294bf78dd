// The built map against the truth near a drive (MapAgreement): hand-built grids with known
// counts.

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/loops/navigate_maps.hpp"

namespace fieldlidar::loops {
namespace {

namespace L = terrain::layer;

GridGeometry ten_by_ten() {
  GridGeometry g;
  g.resolution_m = 0.5;
  g.width = g.height = 10;
  return g;
}

TEST(MapAgreement, CountsBlockedFreeAndMissedCellsNearTheDrive) {
  // Truth: one impassable cell (5, 5). Built: it widened a cell east (6, 5) and a far one
  // (9, 9), missed nothing yet; then a truth-impassable cell called passable.
  Grid2D truth(ten_by_ten());
  auto passable = truth.add_layer("passable", 1.0f);
  passable[truth.geometry().linear_index(5, 5)] = 0.0f;
  Grid2D built(ten_by_ten());
  auto tau = built.add_layer(L::kTraversability, 0.8f);
  auto imp = built.add_layer(L::kImpassable, 0.0f);
  auto pts = built.add_layer(L::kPoints, 5.0f);
  const GridGeometry& g = built.geometry();
  for (auto [x, y] : {std::pair{5, 5}, {6, 5}, {9, 9}}) {
    imp[g.linear_index(x, y)] = 1.0f;
    tau[g.linear_index(x, y)] = 0.0f;
  }
  // A drive along y = 2.75 m (cell row 5) from x = 0.25 to 2.25 m; radius 1 m: rows 3-7,
  // columns up to 6 (cell centres within 1 m of a pose's cell centre).
  std::vector<planning::Pose2> driven;
  for (double x = 0.25; x <= 2.26; x += 0.5) driven.push_back({x, 2.75, 0.0});
  const MapAgreement all = map_agreement(built, truth, driven, 1.0);
  // Unknown cells do not count: no returns behind one, no traversability in another.
  pts[g.linear_index(1, 5)] = 0.0f;
  tau[g.linear_index(2, 5)] = NAN;
  const MapAgreement a = map_agreement(built, truth, driven, 1.0);
  EXPECT_EQ(a.known_cells, all.known_cells - 2);
  EXPECT_EQ(a.radius_m, 1.0);
  EXPECT_EQ(a.passable_blocked, 1u);  // (6, 5); (9, 9) is far
  EXPECT_EQ(a.passable_blocked_beside_impassable, 1u);
  EXPECT_EQ(a.impassable_passable, 0u);
  EXPECT_EQ(a.known_cells - a.truth_passable, 1u);  // (5, 5) itself, blocked both ways
  // The map lets the planner onto the truth's impassable cell.
  imp[g.linear_index(5, 5)] = 0.0f;
  tau[g.linear_index(5, 5)] = 0.5f;
  EXPECT_EQ(map_agreement(built, truth, driven, 1.0).impassable_passable, 1u);
  // No drive, nothing near it.
  EXPECT_EQ(map_agreement(built, truth, {}, 3.0).known_cells, 0u);
}

TEST(MapAgreement, DifferentGridsOrMissingLayersAreErrors) {
  Grid2D truth(ten_by_ten());
  truth.add_layer("passable", 1.0f);
  GridGeometry other = ten_by_ten();
  other.width = 9;
  Grid2D built(other);
  built.add_layer(L::kTraversability, 1.0f);
  built.add_layer(L::kImpassable, 0.0f);
  EXPECT_THROW(map_agreement(built, truth, {}, 3.0), Error);
  Grid2D no_layer(ten_by_ten());
  no_layer.add_layer(L::kTraversability, 1.0f);
  EXPECT_THROW(map_agreement(no_layer, truth, {}, 3.0), Error);
  Grid2D ok(ten_by_ten());
  ok.add_layer(L::kTraversability, 1.0f);
  ok.add_layer(L::kImpassable, 0.0f);
  EXPECT_THROW(map_agreement(ok, truth, {}, NAN), Error);
}

}  // namespace
}  // namespace fieldlidar::loops
