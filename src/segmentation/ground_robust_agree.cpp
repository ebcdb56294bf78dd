// Pass 2 of the robust ground: agreement with the neighbouring cells across sectors.

#include <algorithm>
#include <vector>

#include "ground_robust_cells.hpp"

namespace fieldlidar::segmentation::detail {

// A ground cell standing above the median of its ground neighbours (a flat roof, a table, a dense
// bush top) is rejected; a rejected cell takes the neighbours' median as its expected ground
// height.
void agree_with_neighbours(const PolarGrid& grid, const RobustGroundConfig& config,
                           std::vector<CellFit>& fits) {
  std::vector<float> neighbours;
  struct Update {
    std::size_t cell;
    CellState state;
    float predicted;
  };
  std::vector<Update> updates;  // applied after the pass so every cell sees the pass-1 states
  for (int s = 0; s < grid.sectors(); ++s)
    for (int b = 0; b < grid.bins(); ++b) {
      const std::size_t c = grid.cell(b, s);
      if (fits[c].state == CellState::kEmpty) continue;
      neighbours.clear();
      for (int ds = -2; ds <= 2; ++ds)
        for (int db = -1; db <= 1; ++db) {
          if ((ds == 0 && db == 0) || b + db < 0 || b + db >= grid.bins()) continue;
          const int sn = (s + ds + grid.sectors()) % grid.sectors();
          const CellFit& n = fits[grid.cell(b + db, sn)];
          if (n.state == CellState::kGround) neighbours.push_back(n.elevation);
        }
      if (neighbours.size() < 2) continue;
      auto mid = neighbours.begin() + neighbours.size() / 2;
      std::nth_element(neighbours.begin(), mid, neighbours.end());
      const float median = *mid;
      CellState state = fits[c].state;
      if (state == CellState::kGround && fits[c].elevation > median + float(config.max_step_m))
        state = CellState::kRejected;
      if (state == CellState::kRejected) updates.push_back({c, state, median});
    }
  for (const Update& u : updates) {
    fits[u.cell].state = u.state;
    fits[u.cell].predicted = u.predicted;
  }
}

}  // namespace fieldlidar::segmentation::detail
