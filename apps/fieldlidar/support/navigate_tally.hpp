#pragma once
// The whole of a `fieldlidar navigate --pairs` run in one paragraph: how many goals the truth plan
// reaches were reached, how many drives touched truth-impassable cells, how the driven lengths
// compare with the truth plans, and whether the unreachable goals were reported so.

#include <cstddef>
#include <string>

#include "fieldlidar/loops/navigate.hpp"

namespace fieldlidar::app {

class NavigateTally {
 public:
  /// Bound on the driven length over the truth plan's that a drive is counted within.
  explicit NavigateTally(double ratio_bound = 1.15) : ratio_bound_(ratio_bound) {}

  void add(const loops::NavigateResult& r);
  /// E.g. "12 pairs: 9 of 9 goals the truth plan reaches arrived (8 within 1.15 x its length,
  /// mean 1.062, largest 1.168); 0 drives with the footprint on truth-impassable cells (0
  /// frames; 0 reaching 0.10 m or more into such a cell; 0 meeting an obstacle itself); 3 of 3
  /// goals it cannot reach reported unreachable".
  std::string text() const;

 private:
  double ratio_bound_;
  std::size_t pairs_ = 0, reachable_ = 0, arrived_ = 0, within_ = 0;
  std::size_t unreachable_ = 0, said_unreachable_ = 0, touching_ = 0, frames_ = 0, deep_ = 0;
  std::size_t contact_ = 0;  ///< drives whose footprint met an obstacle's disc itself
  /// A drive whose footprint reached this far into a truth-impassable cell (m) did more than
  /// brush the cell's edge (NavigateResult::max_impassable_depth_m).
  static constexpr double kDeep_m = 0.1;
  double ratio_sum_ = 0, ratio_max_ = 0;
};

}  // namespace fieldlidar::app
