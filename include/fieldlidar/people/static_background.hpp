#pragma once
/// \file An online model of the static background for a sensor that stands still (or scans
/// expressed in a fixed frame): arcs made of points where returns keep coming back scan after
/// scan (chair and table legs, posts) are not people. Beyond the seed: real scans are full of
/// leg-shaped furniture that the arc test alone cannot tell from legs.

#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>

namespace fieldlidar::people {

struct StaticBackgroundConfig {
  double cell_m = 0.10;            ///< grid cell size (m)
  double half_extent_m = 20.0;     ///< the grid covers [-half, half]^2 around the origin (m)
  double rate = 0.02;              ///< exponential averaging rate of a cell's occupancy per scan
  double static_occupancy = 0.35;  ///< a cell occupied this often is background
  double static_fraction = 0.5;    ///< an arc is background when this share of its points is
  int warmup_scans = 20;           ///< nothing is background before this many scans
};

class StaticBackground {
 public:
  explicit StaticBackground(const StaticBackgroundConfig& config = {});
  /// Adds one scan's points (fixed frame, m).
  void update(std::span<const Eigen::Vector2d> points);
  /// True when most points of the arc lie on cells that have been occupied most of the time
  /// (the cell or one of its 8 neighbours, to absorb range noise).
  bool is_static(std::span<const Eigen::Vector2d> arc_points) const;
  int scans() const { return scans_; }

 private:
  int index(const Eigen::Vector2d& p) const;
  double value(int cell) const;  ///< occupancy of a cell now (its decay applied)
  StaticBackgroundConfig config_;
  int side_ = 0;
  int scans_ = 0;
  std::vector<float> occupancy_;
  std::vector<std::uint32_t> stamp_;  ///< last scan that hit the cell (to count a cell once)
};

}  // namespace fieldlidar::people
