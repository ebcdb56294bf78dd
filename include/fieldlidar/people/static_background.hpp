#pragma once
/// \file An online model of the static background for a sensor that stands still (or scans
/// expressed in a fixed frame): arcs made of points where returns keep coming back scan after
/// scan (chair and table legs, posts) are not people. Beyond the seed: real scans are full of
/// leg-shaped furniture that the arc test alone cannot tell from legs.
///
/// The grid rolls with the points it is given: it holds the cells of the last
/// 2 * half_extent_m in each axis (a cell reuses the slot of the cell that far away), so a
/// sensor that drives anywhere in its fixed frame keeps a grid around itself.

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>

namespace fieldlidar::people {

struct StaticBackgroundConfig {
  double cell_m = 0.10;  ///< grid cell size (m)
  /// The grid remembers a square of 2 * half_extent_m around the points it was last given (m).
  double half_extent_m = 20.0;
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
  /// Adds more points to the scan of the last update() with `weight` (0..1) times the rate: a
  /// cell they hit counts `weight` of a hit in this scan (a cell counts once per scan, the
  /// first time it is hit).
  void add(std::span<const Eigen::Vector2d> points, double weight);
  /// True when most points of the arc lie on cells that have been occupied most of the time
  /// (the cell or one of its 8 neighbours, to absorb range noise).
  bool is_static(std::span<const Eigen::Vector2d> arc_points) const;
  int scans() const { return scans_; }

 private:
  using Cell = std::array<int, 2>;  ///< cell indices (floor of the coordinate / cell_m)
  static constexpr int kNoCell = -(1 << 30);
  /// Points farther from the origin are ignored (their cell index would overflow; m).
  static constexpr double kMaxCoordinate_m = 1e6;
  Cell cell_of(const Eigen::Vector2d& p) const;
  std::size_t slot(const Cell& c) const;
  double value(const Cell& c) const;  ///< occupancy of a cell now (its decay applied)
  double full() const;                ///< occupancy of a cell hit in every scan so far
  /// One grid slot, its fields side by side (a lookup touches one cache line).
  struct Slot {
    Cell key = {kNoCell, kNoCell};  ///< the cell the slot holds
    std::uint32_t stamp = 0;        ///< last scan that hit the slot (to count a cell once)
    float occupancy = 0.f;
  };
  static bool holds(const Slot& s, const Cell& c) { return s.key[0] == c[0] && s.key[1] == c[1]; }
  /// (1 - rate)^age, tabulated for the ages met most (std::pow beyond, the same values).
  double decay(std::uint32_t age) const;
  StaticBackgroundConfig config_;
  int side_ = 0;
  int scans_ = 0;
  std::vector<Slot> slots_;
  std::vector<double> decay_;
};

}  // namespace fieldlidar::people
