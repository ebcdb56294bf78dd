// The planner's view of a traversability map: blocked cells, cost tau, footprint masks per
// heading bin and sub-cell position, and the distance to the nearest blocked cell.

#include "fieldlidar/planning/planning_map.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <string>

#include "fieldlidar/core/error.hpp"

namespace fieldlidar::planning {
namespace {

// Cells (dx, dy) relative to the cell whose lower-left corner is the origin that the rectangle
// centred at c (m, from that corner) with heading theta overlaps, by separating axes.
template <typename F>
void for_each_overlap(double cx, double cy, double theta, double half_l, double half_w, double res,
                      F&& f) {
  const double ux = std::cos(theta), uy = std::sin(theta);
  const double vx = -uy, vy = ux;
  const double ex = half_l * std::abs(ux) + half_w * std::abs(vx);  // extent along x
  const double ey = half_l * std::abs(uy) + half_w * std::abs(vy);
  const int x0 = int(std::floor((cx - ex) / res)), x1 = int(std::floor((cx + ex) / res));
  const int y0 = int(std::floor((cy - ey) / res)), y1 = int(std::floor((cy + ey) / res));
  const double h = 0.5 * res;
  const double sq_u = h * (std::abs(ux) + std::abs(uy));  // the square's extent along u or v
  const double sq_v = h * (std::abs(vx) + std::abs(vy));
  for (int iy = y0; iy <= y1; ++iy)
    for (int ix = x0; ix <= x1; ++ix) {
      const double sx = (ix + 0.5) * res - cx, sy = (iy + 0.5) * res - cy;
      if (std::abs(sx * ux + sy * uy) >= half_l + sq_u) continue;
      if (std::abs(sx * vx + sy * vy) >= half_w + sq_v) continue;
      // the x and y axes: already inside the bounding range, touching edges excluded
      if (sx + h <= -ex || sx - h >= ex || sy + h <= -ey || sy - h >= ey) continue;
      f(ix, iy);
    }
}

}  // namespace

PlanningMap::PlanningMap(const Grid2D& map, const terrain::RobotConfig& robot,
                         const MapReadConfig& config)
    : geometry_(map.geometry()), robot_(robot), config_(config) {
  namespace L = terrain::layer;
  if (geometry_.cell_count() == 0) throw Error("planning map: the grid is empty");
  if (!(geometry_.resolution_m > 0.0))
    throw Error("planning map: resolution_m " + std::to_string(geometry_.resolution_m));
  if (!map.has_layer(L::kTraversability))
    throw Error(std::string("planning map: no layer '") + L::kTraversability + "'");
  for (double side : {robot.length_m, robot.width_m})
    if (!(side > 0.0 && side <= 20.0))
      throw Error("planning map: robot side " + std::to_string(side) + " m not in (0, 20]");
  if (!(config.footprint_margin_m >= 0.0 && config.footprint_margin_m <= 5.0))
    throw Error("planning map: footprint_margin_m " + std::to_string(config.footprint_margin_m));
  if (!(config.unknown_tau >= 0.0 && config.unknown_tau <= 1.0))
    throw Error("planning map: unknown_tau " + std::to_string(config.unknown_tau));
  // The footprint masks grow with the square of the cells the footprint spans (a 1.2 m robot on
  // 5 mm cells took 1.25 GB): such a map is far finer than a plan needs.
  const double diagonal_m = 2.0 * std::hypot(0.5 * robot.length_m + config.footprint_margin_m,
                                             0.5 * robot.width_m + config.footprint_margin_m);
  if (diagonal_m / geometry_.resolution_m > kMaxFootprintCells) {
    char msg[200];
    std::snprintf(msg, sizeof msg,
                  "planning map: cells of %g m make the robot's footprint (with its margin) %.0f "
                  "cells across, more than %d: use a map of cells of %.3f m or more",
                  geometry_.resolution_m, diagonal_m / geometry_.resolution_m, kMaxFootprintCells,
                  diagonal_m / kMaxFootprintCells);
    throw Error(msg);
  }

  const auto tau = map.layer(L::kTraversability);
  const bool has_imp = map.has_layer(L::kImpassable), has_pts = map.has_layer(L::kPoints);
  const auto imp = has_imp ? map.layer(L::kImpassable) : decltype(tau){};
  const auto pts = has_pts ? map.layer(L::kPoints) : decltype(tau){};
  const std::size_t n = geometry_.cell_count();
  tau_.assign(n, float(config.unknown_tau));
  blocked_.assign(n, 0);
  known_.assign(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const CellRead read = read_cell(tau[i], has_imp ? imp[i] : 0.0f, has_pts ? pts[i] : 1.0f);
    if (read == CellRead::kUnknown) {
      blocked_[i] = !config.allow_unknown;
      continue;
    }
    known_[i] = 1;
    ++known_cells_;
    tau_[i] = std::clamp(std::isfinite(tau[i]) ? tau[i] : 0.0f, 0.0f, 1.0f);
    blocked_[i] = read == CellRead::kBlocked;
  }
  build_masks();
  build_distance_field();
}

void PlanningMap::build_masks() {
  const double res = geometry_.resolution_m;
  const double half_l = 0.5 * robot_.length_m + config_.footprint_margin_m;
  const double half_w = 0.5 * robot_.width_m + config_.footprint_margin_m;
  const double sub = res / kSubcells;
  const double bin = 2.0 * std::numbers::pi / kFootprintHeadingBins;
  // Any centre within the sub-cell (half-diagonal) and any heading within half a bin of the
  // bin's (the corner's arc) stays inside the inflated rectangle.
  const double inflate = sub * std::sqrt(0.5) + std::hypot(half_l, half_w) * 0.5 * bin;
  masks_.assign(std::size_t(kFootprintHeadingBins) * kSubcells * kSubcells, {});
  reach_cells_ = 0;
  for (int b = 0; b < kFootprintHeadingBins; ++b)
    for (int sy = 0; sy < kSubcells; ++sy)
      for (int sx = 0; sx < kSubcells; ++sx) {
        auto& mask = masks_[(std::size_t(b) * kSubcells + sy) * kSubcells + sx];
        for_each_overlap((sx + 0.5) * sub, (sy + 0.5) * sub, b * bin, half_l + inflate,
                         half_w + inflate, res, [&](int dx, int dy) {
                           mask.push_back({std::int16_t(dx), std::int16_t(dy)});
                           reach_cells_ = std::max({reach_cells_, std::abs(dx), std::abs(dy)});
                         });
      }
  linear_masks_.clear();
  for (const auto& mask : masks_) {
    auto& linear = linear_masks_.emplace_back();
    for (const Offset& o : mask) linear.push_back(std::int32_t(o.dy) * geometry_.width + o.dx);
  }
}

long PlanningMap::cell_index(double x_m, double y_m) const {
  const double fx = (x_m - geometry_.origin_m.x()) / geometry_.resolution_m;
  const double fy = (y_m - geometry_.origin_m.y()) / geometry_.resolution_m;
  if (!(fx >= 0.0 && fy >= 0.0 && fx < geometry_.width && fy < geometry_.height)) return -1;
  return long(geometry_.linear_index(int(fx), int(fy)));
}

bool PlanningMap::pose_free(const Pose2& pose) const {
  const double fx = (pose.x_m - geometry_.origin_m.x()) / geometry_.resolution_m;
  const double fy = (pose.y_m - geometry_.origin_m.y()) / geometry_.resolution_m;
  if (!(fx >= 0.0 && fy >= 0.0 && fx < geometry_.width && fy < geometry_.height)) return false;
  if (!std::isfinite(pose.yaw_rad)) return false;
  const int ix = int(fx), iy = int(fy);
  const int sx = std::min(kSubcells - 1, int((fx - ix) * kSubcells));
  const int sy = std::min(kSubcells - 1, int((fy - iy) * kSubcells));
  const double bin = 2.0 * std::numbers::pi / kFootprintHeadingBins;
  int b = int(std::lround(pose.yaw_rad / bin)) % kFootprintHeadingBins;
  if (b < 0) b += kFootprintHeadingBins;
  const std::size_t m = (std::size_t(b) * kSubcells + sy) * kSubcells + sx;
  if (ix >= reach_cells_ && iy >= reach_cells_ && ix + reach_cells_ < geometry_.width &&
      iy + reach_cells_ < geometry_.height) {
    const std::uint8_t* at = blocked_.data() + std::size_t(iy) * geometry_.width + ix;
    for (std::int32_t o : linear_masks_[m])
      if (at[o]) return false;
    return true;
  }
  for (const Offset& o : masks_[m]) {
    const int cx = ix + o.dx, cy = iy + o.dy;
    if (!geometry_.contains(cx, cy) || blocked_[std::size_t(cy) * geometry_.width + cx])
      return false;
  }
  return true;
}

bool PlanningMap::footprint_hits_blocked(const Pose2& pose, double margin_m) const {
  for (long i : rectangle_cells(geometry_, pose, 0.5 * robot_.length_m + margin_m,
                                0.5 * robot_.width_m + margin_m))
    if (i < 0 || blocked_[std::size_t(i)]) return true;
  return false;
}

std::vector<long> rectangle_cells(const GridGeometry& geometry, const Pose2& pose,
                                  double half_length_m, double half_width_m) {
  std::vector<long> cells;
  for_each_overlap(
      pose.x_m - geometry.origin_m.x(), pose.y_m - geometry.origin_m.y(), pose.yaw_rad,
      half_length_m, half_width_m, geometry.resolution_m, [&](int ix, int iy) {
        cells.push_back(geometry.contains(ix, iy) ? long(geometry.linear_index(ix, iy)) : -1L);
      });
  return cells;
}

// Felzenszwalb & Huttenlocher's exact squared Euclidean distance transform, rows then columns
// (in cells; 1e20 marks "no blocked cell in this row yet").
namespace {
void edt_1d(const double* f, double* out, int n, std::vector<int>& v, std::vector<double>& z) {
  int k = 0;
  v[0] = 0;
  z[0] = -1e300;
  z[1] = 1e300;
  for (int q = 1; q < n; ++q) {
    double s = 0.0;
    while (true) {
      const int p = v[k];
      s = ((f[q] + double(q) * q) - (f[p] + double(p) * p)) / (2.0 * (q - p));
      if (s > z[k]) break;
      --k;
    }
    ++k;
    v[k] = q;
    z[k] = s;
    z[k + 1] = 1e300;
  }
  k = 0;
  for (int q = 0; q < n; ++q) {
    while (z[k + 1] < q) ++k;
    const double dq = double(q - v[k]);
    out[q] = dq * dq + f[v[k]];
  }
}
}  // namespace

void PlanningMap::build_distance_field() {
  const int w = geometry_.width, h = geometry_.height;
  const double inf = 1e20;
  std::vector<double> d(std::size_t(w) * h);
  for (std::size_t i = 0; i < d.size(); ++i) d[i] = blocked_[i] ? 0.0 : inf;
  const int n = std::max(w, h);
  std::vector<int> v(n + 1);
  std::vector<double> z(n + 2), in(n), out(n);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) in[x] = d[std::size_t(y) * w + x];
    edt_1d(in.data(), out.data(), w, v, z);
    for (int x = 0; x < w; ++x) d[std::size_t(y) * w + x] = out[x];
  }
  for (int x = 0; x < w; ++x) {
    for (int y = 0; y < h; ++y) in[y] = d[std::size_t(y) * w + x];
    edt_1d(in.data(), out.data(), h, v, z);
    for (int y = 0; y < h; ++y) d[std::size_t(y) * w + x] = out[y];
  }
  distance_m_.resize(d.size());
  for (std::size_t i = 0; i < d.size(); ++i)
    distance_m_[i] = d[i] >= inf * 0.5 ? 1e6f : float(std::sqrt(d[i]) * geometry_.resolution_m);
}

double PlanningMap::obstacle_distance_at(double x_m, double y_m) const {
  const double fx = (x_m - geometry_.origin_m.x()) / geometry_.resolution_m - 0.5;
  const double fy = (y_m - geometry_.origin_m.y()) / geometry_.resolution_m - 0.5;
  const int x0 = std::clamp(int(std::floor(fx)), 0, geometry_.width - 1);
  const int y0 = std::clamp(int(std::floor(fy)), 0, geometry_.height - 1);
  const int x1 = std::min(x0 + 1, geometry_.width - 1), y1 = std::min(y0 + 1, geometry_.height - 1);
  const double tx = std::clamp(fx - x0, 0.0, 1.0), ty = std::clamp(fy - y0, 0.0, 1.0);
  auto at = [&](int x, int y) { return double(distance_m_[std::size_t(y) * geometry_.width + x]); };
  return (1 - ty) * ((1 - tx) * at(x0, y0) + tx * at(x1, y0)) +
         ty * ((1 - tx) * at(x0, y1) + tx * at(x1, y1));
}

}  // namespace fieldlidar::planning
