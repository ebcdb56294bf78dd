// The robust default ground segmentation: local plane fits on a polar grid, grown outward from
// the sensor with uprightness, flatness and height-continuity tests. The sensor height is
// estimated from the cloud (estimate_sensor_height), so a wrong or unknown mounting height does
// not matter; no state is kept between frames.

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include <Eigen/Eigenvalues>

#include "fieldlidar/segmentation/ground.hpp"
#include "ground_plane.hpp"
#include "polar_grid.hpp"

namespace fieldlidar::segmentation {
namespace {

enum class CellState : std::uint8_t { kEmpty, kGround, kRejected };

struct CellFit {
  Eigen::Vector3f normal{0.f, 0.f, 1.f};  ///< up-pointing unit normal of the low points
  float d = 0.f;                          ///< plane: normal . p + d = 0
  float z_min = 0.f;                      ///< m, lowest return of the cell
  float elevation = 0.f;                  ///< m, plane height at the cell's centre
  float predicted = 0.f;                  ///< m, ground height expected from the inner cells
  float flatness = 0.f;                   ///< m, sqrt of the smallest eigenvalue
  bool upright = true;
  CellState state = CellState::kEmpty;

  /// Height of (x, y, z) above the cell's ground plane, along z (m).
  template <class P>
  float height_above(const P& p) const {
    return (normal.x() * p.x + normal.y() * p.y + normal.z() * p.z + d) / normal.z();
  }
};

// PCA of the cell's low points (within seed_band_m of its lowest return).
void fit_cell(std::span<const CellPoint> members, double seed_band_m, float max_cos, float cx,
              float cy, CellFit& fit) {
  float z_min = std::numeric_limits<float>::max();
  for (const CellPoint& p : members) z_min = std::min(z_min, p.z);
  fit.z_min = z_min;
  const float band = z_min + float(seed_band_m);
  // Moments about the lowest return (small numbers, no cancellation): 3 sums, 6 products.
  const CellPoint& o = members.front();
  double sx = 0, sy = 0, sz = 0, xx = 0, xy = 0, xz = 0, yy = 0, yz = 0, zz = 0;
  int n = 0;
  for (const CellPoint& p : members) {
    if (p.z > band) continue;
    const double x = p.x - o.x, y = p.y - o.y, z = p.z - o.z;
    sx += x;
    sy += y;
    sz += z;
    xx += x * x;
    xy += x * y;
    xz += x * z;
    yy += y * y;
    yz += y * z;
    zz += z * z;
    ++n;
  }
  const Eigen::Vector3d local_mean = Eigen::Vector3d(sx, sy, sz) / n;
  const Eigen::Vector3d mean = local_mean + Eigen::Vector3d(o.x, o.y, o.z);
  fit.normal = {0.f, 0.f, 1.f};
  fit.flatness = 0.f;
  fit.upright = true;
  if (n >= 4) {
    Eigen::Matrix3d cov;
    cov << xx, xy, xz, xy, yy, yz, xz, yz, zz;
    cov = cov / n - local_mean * local_mean.transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
    es.computeDirect(cov);
    const Eigen::Vector3d ev = es.eigenvalues().cwiseMax(0.0);
    // Points on a single scan line span one direction only: the plane is undetermined, keep it
    // horizontal through their mean.
    if (std::sqrt(ev(1)) > 0.04) {
      Eigen::Vector3d nrm = es.eigenvectors().col(0);
      if (nrm.z() < 0) nrm = -nrm;
      fit.normal = nrm.cast<float>();
      fit.flatness = float(std::sqrt(ev(0)));
      fit.upright = fit.normal.z() >= max_cos;
    }
  }
  if (!fit.upright) fit.normal = {0.f, 0.f, 1.f};
  fit.d = -fit.normal.cast<double>().dot(mean);
  fit.elevation = -(fit.normal.x() * cx + fit.normal.y() * cy + fit.d) / fit.normal.z();
}

// Foot-of-a-face test: returns of one azimuth column ordered by elevation (z / horizontal range
// is monotonic in it) are, to the column's width, the beams of neighbouring rings. A pair of
// them that rises steeply lies on a vertical face -- a trunk, a hedge, the base of a shrub -- and
// a return there within a few centimetres of the ground plane passes the plane tests but is not
// ground. Ground between rings rises at most at the ground slope (< 22 deg), far from a face.
// The upper return of a steep pair is rejected; the lower one only when the pair is nearly
// vertical, since real ground in front of a face forms a steep pair with the face's lowest hit.
void reject_face_feet(const PointCloud& cloud, const RobustGroundConfig& config, int columns,
                      GroundResult& result) {
  struct ColumnPoint {
    float elevation;  ///< z / rho, monotonic in the beam elevation
    float rho;        ///< m, horizontal range
    float z;          ///< m
    std::uint32_t index;
  };
  const std::size_t n = cloud.size();
  const float max_rho = float(config.max_range_m);
  const float col_scale = float(columns) / (2.f * std::numbers::pi_v<float>);
  std::vector<std::uint32_t> column_of(n, std::uint32_t(-1));
  std::vector<std::uint32_t> offsets(std::size_t(columns) + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const Point& p = cloud.points[i];
    if (!valid_point(p)) continue;
    const float rho = std::sqrt(p.x * p.x + p.y * p.y);
    if (rho < 0.3f || rho > max_rho) continue;
    int col = int((fast_atan2(p.y, p.x) + std::numbers::pi_v<float>)*col_scale);
    col = std::clamp(col, 0, columns - 1);
    column_of[i] = std::uint32_t(col);
    ++offsets[std::size_t(col) + 1];
  }
  for (int c = 0; c < columns; ++c) offsets[std::size_t(c) + 1] += offsets[std::size_t(c)];
  std::vector<ColumnPoint> pts(offsets.back());
  {
    std::vector<std::uint32_t> fill(offsets.begin(), offsets.end() - 1);
    for (std::size_t i = 0; i < n; ++i) {
      if (column_of[i] == std::uint32_t(-1)) continue;
      const Point& p = cloud.points[i];
      const float rho = std::sqrt(p.x * p.x + p.y * p.y);
      pts[fill[column_of[i]]++] = {p.z / rho, rho, p.z, std::uint32_t(i)};
    }
  }
  const float cot_steep = float(1.0 / std::tan(config.face_steep_deg * std::numbers::pi / 180.0));
  const float min_rise = float(config.face_min_rise_m);
  const float cot_foot = float(1.0 / std::tan(config.face_foot_deg * std::numbers::pi / 180.0));
  const int k_max = std::max(1, config.face_neighbours);
  std::vector<std::uint32_t> feet;
  for (int c = 0; c < columns; ++c) {
    const auto first = pts.begin() + offsets[std::size_t(c)];
    const auto last = pts.begin() + offsets[std::size_t(c) + 1];
    std::sort(first, last,
              [](const ColumnPoint& a, const ColumnPoint& b) { return a.elevation < b.elevation; });
    for (auto it = first; it != last; ++it) {
      const auto stop = std::min(last, it + 1 + k_max);
      for (auto up = it + 1; up != stop; ++up) {
        const float rise = up->z - it->z;
        const float run = std::abs(up->rho - it->rho);
        if (rise < min_rise || run > rise * cot_steep) continue;
        if (result.is_ground[up->index]) feet.push_back(up->index);
        if (run <= rise * cot_foot && result.is_ground[it->index]) feet.push_back(it->index);
      }
    }
  }
  for (const std::uint32_t i : feet)
    if (result.is_ground[i]) {
      result.is_ground[i] = 0;
      --result.ground_count;
    }
}

}  // namespace

GroundResult ground_robust(const PointCloud& cloud, const SensorModel& sensor,
                           const RobustGroundConfig& config) {
  GroundResult result;
  result.is_ground.assign(cloud.size(), 0);
  const double max_slope_rad = config.max_slope_deg * std::numbers::pi / 180.0;
  // The ground near the sensor as a tilted plane: off-road the vehicle pitches and rolls, and the
  // mounting height is rarely known to a few centimetres.
  const PolarGrid grid(config.min_cell_m, config.cell_growth, config.max_range_m,
                       config.sector_deg);
  const PolarCells cells = grid.assign(cloud);

  // The lowest return of each cell between 1.5 m and near_range_m (below the sensor) feeds the
  // prior plane.
  std::vector<Eigen::Vector3f> lows;
  for (int s = 0; s < grid.sectors(); ++s)
    for (int b = 0; b < grid.bins() && grid.bin_centre_m(b) < config.near_range_m; ++b) {
      if (grid.bin_centre_m(b) < 1.5f) continue;
      const CellPoint* low = nullptr;
      for (const CellPoint& p : cells.points(grid.cell(b, s)))
        if (!low || p.z < low->z) low = &p;
      if (low && low->z < 0.f) lows.emplace_back(low->x, low->y, low->z);
    }
  NearGroundPlane prior = fit_plane_to_lows(lows, max_slope_rad);
  if (!prior.found) prior.c = -(sensor.mounting_height_m > 0 ? sensor.mounting_height_m : 1.0);
  result.sensor_height_m = -prior.c / std::sqrt(1.0 + prior.a * prior.a + prior.b * prior.b);

  const float max_cos = float(std::cos(max_slope_rad));
  const double tan_slope = std::tan(max_slope_rad);
  const double tan_bend = std::tan(config.max_bend_deg * std::numbers::pi / 180.0);
  std::vector<CellFit> fits(grid.cell_count());

  // Pass 1, per sector from the sensor outward: a cell is ground when its low-point plane is
  // upright and flat and continues the ground of the inner cells (or, before any, the prior).
  for (int s = 0; s < grid.sectors(); ++s) {
    const float a_mid = grid.sector_centre_rad(s);
    const float ca = std::cos(a_mid), sa = std::sin(a_mid);
    bool anchored = false;
    double ref_z = 0.0, ref_r = 0.0, ref_grad = 0.0;
    for (int b = 0; b < grid.bins(); ++b) {
      const std::size_t c = grid.cell(b, s);
      const auto members = cells.points(c);
      if (members.empty()) continue;
      const float r_mid = grid.bin_centre_m(b);
      CellFit& fit = fits[c];
      fit_cell(members, config.seed_band_m, max_cos, r_mid * ca, r_mid * sa, fit);
      double predicted, tolerance;
      if (anchored) {
        const double dr = r_mid - ref_r;
        predicted = ref_z + ref_grad * dr;
        tolerance = config.max_step_m + tan_bend * dr;
      } else {
        predicted = prior.height_at(r_mid * ca, r_mid * sa);
        tolerance = config.max_step_m + tan_slope * std::max(0.0, r_mid - config.near_range_m);
      }
      fit.predicted = float(predicted);
      const bool continuous = std::abs(fit.elevation - predicted) <= tolerance;
      const bool flat = fit.flatness <= config.max_flatness_m;
      if (continuous && fit.upright && flat) {
        fit.state = CellState::kGround;
        anchored = true;
        ref_z = fit.elevation;
        ref_r = r_mid;
        // Radial gradient of the cell's plane, to follow a hill outward.
        const double g = -(fit.normal.x() * ca + fit.normal.y() * sa) / fit.normal.z();
        ref_grad = std::clamp(g, -tan_slope, tan_slope);
      } else {
        fit.state = CellState::kRejected;
      }
    }
  }

  // Pass 2: agreement with the neighbouring cells across sectors. A ground cell standing above
  // the median of its ground neighbours (a flat roof, a table, a dense bush top) is rejected; a
  // rejected cell takes the neighbours' median as its expected ground height.
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

  const float above = float(config.ground_above_m), below = float(config.ground_below_m);
  const float clutter_top = float(config.clutter_height_m);
  const float cluttered_above = float(config.cluttered_above_m);
  const float rejected_above = float(config.rejected_above_m);
  for (std::size_t c = 0; c < fits.size(); ++c) {
    const CellFit& fit = fits[c];
    if (fit.state == CellState::kEmpty) continue;
    if (config.max_roughness_m > 0 && fit.state == CellState::kGround) {
      double sq = 0;
      std::size_t n = 0;
      for (const CellPoint& p : cells.points(c)) {
        const float h = fit.height_above(p);
        if (std::abs(h) < 0.3f) {
          sq += double(h) * h;
          ++n;
        }
      }
      if (n >= 3 && std::sqrt(sq / double(n)) > config.max_roughness_m) continue;
    }
    float cell_above = fit.state == CellState::kGround ? above : rejected_above;
    if (config.max_clutter_ratio > 0 && fit.state == CellState::kGround) {
      std::size_t low = 0, clutter = 0;
      for (const CellPoint& p : cells.points(c)) {
        const float h = fit.height_above(p);
        if (h <= above)
          ++low;
        else if (h <= clutter_top)
          ++clutter;
      }
      if (double(clutter) > config.max_clutter_ratio * double(low)) cell_above = cluttered_above;
    }
    const auto pts = cells.points(c);
    const auto idx = cells.members(c);
    for (std::size_t k = 0; k < pts.size(); ++k) {
      const CellPoint& p = pts[k];
      const std::uint32_t i = idx[k];
      const float h = fit.state == CellState::kGround ? fit.height_above(p) : p.z - fit.predicted;
      if (h <= cell_above && h >= -below) {
        result.is_ground[i] = 1;
        ++result.ground_count;
      }
    }
  }
  // Dense beam tables (64+ rings) resolve the faces themselves in the plane fits and gain
  // nothing measurable from the test (RELLIS-3D: F1 0.9563 either way), at 2-3x the cost.
  const int face_columns = config.face_columns >= 0 ? config.face_columns
                           : sensor.rings() <= 32   ? sensor.columns
                                                    : 0;
  if (face_columns > 0) reject_face_feet(cloud, config, face_columns, result);
  return result;
}

}  // namespace fieldlidar::segmentation
