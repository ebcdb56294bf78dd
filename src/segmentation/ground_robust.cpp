// The robust default ground segmentation: local plane fits on a polar grid, grown outward from
// the sensor with uprightness, flatness and height-continuity tests. The sensor height is
// estimated from the cloud (estimate_sensor_height), so a wrong or unknown mounting height does
// not matter; no state is kept between frames.

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include <Eigen/Eigenvalues>

#include "fieldlidar/segmentation/ground.hpp"
#include "ground_plane.hpp"
#include "polar_grid.hpp"

namespace fieldlidar::segmentation {
namespace {

enum class CellState : std::uint8_t { kEmpty, kGround, kRejected };

// What the passes after the fit need of a cell, kept small: the cells of a frame are swept
// several times.
struct CellFit {
  float elevation = 0.f;               ///< m, plane height at the cell's centre
  float predicted = 0.f;               ///< m, ground height expected from the inner cells
  float gx = 0.f, gy = 0.f, g0 = 0.f;  ///< plane as z = -(gx x + gy y + g0)
  CellState state = CellState::kEmpty;

  /// Height of (x, y, z) above the cell's ground plane, along z (m).
  template <class P>
  float height_above(const P& p) const {
    return gx * p.x + gy * p.y + p.z + g0;
  }
  /// Height above the cell's ground: its plane in a ground cell, else the ground expected from
  /// the neighbouring cells (m).
  template <class P>
  float height_over_ground(const P& p) const {
    return state == CellState::kGround ? height_above(p) : p.z - predicted;
  }
};

// The fit's own tests, used once.
struct PlaneFit {
  Eigen::Vector3f normal{0.f, 0.f, 1.f};  ///< up-pointing unit normal of the low points
  float flatness = 0.f;                   ///< m, sqrt of the smallest eigenvalue
  bool upright = true;
  /// The low points lie along one scan line: the plane's tilt is unknown (kept horizontal).
  bool line_only = false;
};

// A line-only cell's low points (within `band` of z): their mean horizontal range (m), and
// whether nothing in the cell lies above them.
struct LineStats {
  float rho = 0.f;
  bool alone = false;
};

LineStats line_stats(std::span<const CellPoint> members, const float* rho, float band) {
  double sum = 0;
  int n = 0;
  for (std::size_t k = 0; k < members.size(); ++k)
    if (members[k].z <= band) {
      sum += rho[k];
      ++n;
    }
  return {float(sum / std::max(1, n)), n == int(members.size())};
}

struct SmallestEigen {
  double value = 0, second_value = 0;                 ///< the two smallest eigenvalues, >= 0
  Eigen::Vector3d vector = Eigen::Vector3d::UnitZ();  ///< unit eigenvector of `value`
};

// Smallest eigenpair of a symmetric positive semi-definite 3x3 matrix without trigonometry
// (Eigen's closed form spends most of its time in acos/cos/sin): Newton's method on the
// characteristic polynomial from 0 climbs monotonically to the smallest root, the second one
// follows from the other coefficients, the vector from cross products of (C - l1 I)'s rows.
SmallestEigen smallest_eigen(const Eigen::Matrix3d& c) {
  const double c1 = c.trace();
  const double c2 = c(0, 0) * c(1, 1) - c(0, 1) * c(0, 1) + c(0, 0) * c(2, 2) - c(0, 2) * c(0, 2) +
                    c(1, 1) * c(2, 2) - c(1, 2) * c(1, 2);
  const double c3 = c.determinant();
  SmallestEigen out;
  // p(l) = det(C - l I) = -l^3 + c1 l^2 - c2 l + c3, convex left of its smallest root.
  double l = 0;
  for (int it = 0; it < 100 && c3 > 0; ++it) {
    const double p = ((-l + c1) * l - c2) * l + c3;
    const double dp = (-3 * l + 2 * c1) * l - c2;
    if (!(dp < 0)) break;
    const double step = p / dp;
    l -= step;
    if (std::abs(step) <= 1e-15 * c1) break;
  }
  out.value = std::max(l, 0.0);
  const double s = c1 - out.value, q = c2 - out.value * s;  // l2 + l3 and l2 * l3
  out.second_value = std::max(0.0, 0.5 * (s - std::sqrt(std::max(0.0, s * s - 4 * q))));
  const Eigen::Matrix3d m = c - out.value * Eigen::Matrix3d::Identity();
  const Eigen::Vector3d v01 = m.row(0).cross(m.row(1)), v02 = m.row(0).cross(m.row(2)),
                        v12 = m.row(1).cross(m.row(2));
  const double n01 = v01.squaredNorm(), n02 = v02.squaredNorm(), n12 = v12.squaredNorm();
  const double best = std::max({n01, n02, n12});
  if (best > 1e-30 * c1 * c1 * c1 * c1) {
    out.vector = (n01 == best ? v01 : n02 == best ? v02 : v12) / std::sqrt(best);
  } else {  // repeated smallest eigenvalue: any vector of its eigenspace will do
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
    es.computeDirect(c);
    out.vector = es.eigenvectors().col(0);
  }
  return out;
}

// PCA of the cell's low points (within seed_band_m of its lowest return).
PlaneFit fit_cell(std::span<const CellPoint> members, float z_min, double seed_band_m,
                  float max_cos, float cx, float cy, CellFit& fit) {
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
  PlaneFit out;
  if (n >= 4) {
    Eigen::Matrix3d cov;
    cov << xx, xy, xz, xy, yy, yz, xz, yz, zz;
    cov = cov / n - local_mean * local_mean.transpose();
    const SmallestEigen es = smallest_eigen(cov);
    // Points on a single scan line span one direction only: the plane is undetermined, keep it
    // horizontal through their mean.
    if (std::sqrt(es.second_value) > 0.04) {
      Eigen::Vector3d nrm = es.vector;
      if (nrm.z() < 0) nrm = -nrm;
      out.normal = nrm.cast<float>();
      out.flatness = float(std::sqrt(es.value));
      out.upright = out.normal.z() >= max_cos;
    } else {
      out.line_only = true;
    }
  } else {
    out.line_only = true;
  }
  if (!out.upright) out.normal = {0.f, 0.f, 1.f};
  const Eigen::Vector3f& nm = out.normal;
  const float d = float(-nm.cast<double>().dot(mean));  // plane: normal . p + d = 0
  fit.elevation = -(nm.x() * cx + nm.y() * cy + d) / nm.z();
  fit.gx = nm.x() / nm.z();
  fit.gy = nm.y() / nm.z();
  fit.g0 = d / nm.z();
  return out;
}

// One return of an azimuth column.
struct ColumnReturn {
  float elevation;  ///< z / rho, monotonic in the beam elevation
  float rho;        ///< m, horizontal range
  float z;          ///< m
  std::uint32_t index;
};

// The pair tests over one column, returns in ascending elevation.
class FaceTests {
 public:
  explicit FaceTests(const RobustGroundConfig& config)
      : cot_steep_(float(1.0 / std::tan(config.face_steep_deg * std::numbers::pi / 180.0))),
        cot_foot_(float(1.0 / std::tan(config.face_foot_deg * std::numbers::pi / 180.0))),
        min_rise_(float(config.face_min_rise_m)),
        back_rise_(float(config.face_back_rise_m)),
        back_top_(float(config.face_back_top_m)),
        back_run_(float(config.face_back_run_m)),
        back_reach_(float(config.face_back_reach_m)),
        back_flat_(float(config.face_back_flat_m)),
        flat_gap_(float(config.face_flat_gap_m)),
        k_max_(std::max(1, config.face_neighbours)) {}

  void column(std::span<const ColumnReturn> col, const std::vector<std::uint8_t>& is_ground,
              std::vector<std::uint32_t>& feet) const {
    const std::size_t m = col.size();
    for (std::size_t a = 0; a + 1 < m; ++a) {
      const ColumnReturn& lo = col[a];
      // Ground running on to the lower return: it continues the return below it on the level,
      // from at most flat_gap_ nearer (not across a shadow).
      const bool flat_run = a > 0 && std::abs(lo.z - col[a - 1].z) <= back_flat_ &&
                            lo.rho - col[a - 1].rho <= flat_gap_;
      const std::size_t stop = std::min(m, a + 1 + std::size_t(k_max_));
      for (std::size_t b = a + 1; b < stop; ++b) {
        const ColumnReturn& up = col[b];
        const float rise = up.z - lo.z;
        const float run = up.rho - lo.rho;
        if (rise >= back_rise_ && rise <= back_top_ && run <= back_run_ && run >= -back_reach_) {
          // An overhang: ground may run on under it.
          if (is_ground[up.index]) feet.push_back(up.index);
          if (is_ground[lo.index] && !flat_run) feet.push_back(lo.index);
          continue;
        }
        if (rise < min_rise_ || std::abs(run) > rise * cot_steep_) continue;
        // A face: the lower return is its foot unless the ground runs on to it.
        if (is_ground[up.index]) feet.push_back(up.index);
        if (std::abs(run) <= rise * cot_foot_ && is_ground[lo.index] && !flat_run)
          feet.push_back(lo.index);
      }
    }
  }

 private:
  float cot_steep_, cot_foot_, min_rise_, back_rise_, back_top_, back_run_, back_reach_, back_flat_,
      flat_gap_;
  int k_max_;
};

// Foot-of-a-face test: returns of one azimuth column ordered by elevation are, to the column's
// width, the beams of neighbouring rings. A pair of them that rises steeply lies on a vertical
// face -- a trunk, a hedge, the base of a shrub -- and a return there within a few centimetres
// of the ground plane passes the plane tests but is not ground. Ground between rings rises at
// most at the ground slope (< 22 deg), far from a face. The upper return of a steep pair is
// rejected; the lower one only when the pair is nearly vertical, since real ground in front of a
// face forms a steep pair with the face's lowest hit. An undercut -- the return above nearer
// the sensor than the one below, a few centimetres to decimetres higher -- is the overhanging
// flank of a bush or hedge over its foot, and both are rejected unless the lower one continues
// the return below it on the level (ground running on under the overhang).
// With a ring field the column is an image column indexed by ring (ascending elevation, no
// sorting); without one the returns of a column are sorted by z / rho.
void reject_face_feet(const PolarGrid& grid, const PolarCells& cells,
                      const RobustGroundConfig& config, int columns, int rings,
                      GroundResult& result) {
  const std::size_t m = cells.order.size();
  const float max_rho = float(config.max_range_m);
  const FaceTests tests(config);
  std::vector<std::uint32_t> feet;
  const auto column_of = [&columns](std::uint16_t az) {
    return int((std::uint32_t(az) * std::uint32_t(columns)) >> 16);
  };
  if (rings > 0) {
    // Per polar sector, a small image of its columns x rings holding positions k in `cells` (the
    // last return wins a duplicate). The sector's points are contiguous in `cells` and its
    // columns nest in it (columns is a multiple of the sector count), so the image stays in L1.
    const int sectors = grid.sectors();
    const int per_sector = std::max(1, columns / sectors);
    columns = per_sector * sectors;
    const std::size_t bins = std::size_t(grid.bins());
    std::vector<std::uint32_t> image(std::size_t(per_sector) * std::size_t(rings));
    std::vector<ColumnReturn> col;
    col.reserve(std::size_t(rings));
    for (int s = 0; s < sectors; ++s) {
      const std::uint32_t k0 = cells.offsets[std::size_t(s) * bins];
      const std::uint32_t k1 = cells.offsets[std::size_t(s + 1) * bins];
      if (k1 - k0 < 2) continue;
      std::fill(image.begin(), image.end(), std::uint32_t(-1));
      const int c0 = s * per_sector;
      for (std::uint32_t k = k0; k < k1; ++k) {
        const std::uint16_t ring = cells.ring[k];
        const float rho = cells.rho[k];
        if (ring >= rings || rho < 0.3f || rho > max_rho) continue;
        const int c = std::clamp(column_of(cells.azimuth[k]) - c0, 0, per_sector - 1);
        image[std::size_t(c) * rings + ring] = k;
      }
      for (int c = 0; c < per_sector; ++c) {
        col.clear();
        const std::uint32_t* first = image.data() + std::size_t(c) * rings;
        for (int r = 0; r < rings; ++r) {
          const std::uint32_t k = first[r];
          if (k != std::uint32_t(-1))
            col.push_back({0.f, cells.rho[k], cells.xyz[k].z, cells.order[k]});
        }
        if (col.size() >= 2) tests.column(col, result.is_ground, feet);
      }
    }
  } else {
    std::vector<std::uint32_t> offsets(std::size_t(columns) + 1, 0);
    std::vector<std::int32_t> col_of(m, -1);
    for (std::size_t k = 0; k < m; ++k) {
      const float rho = cells.rho[k];
      if (rho < 0.3f || rho > max_rho) continue;
      col_of[k] = column_of(cells.azimuth[k]);
      ++offsets[std::size_t(col_of[k]) + 1];
    }
    for (int c = 0; c < columns; ++c) offsets[std::size_t(c) + 1] += offsets[std::size_t(c)];
    std::vector<ColumnReturn> pts(offsets.back());
    std::vector<std::uint32_t> fill(offsets.begin(), offsets.end() - 1);
    for (std::size_t k = 0; k < m; ++k) {
      if (col_of[k] < 0) continue;
      const float rho = cells.rho[k], z = cells.xyz[k].z;
      pts[fill[std::size_t(col_of[k])]++] = {z / rho, rho, z, cells.order[k]};
    }
    for (int c = 0; c < columns; ++c) {
      const auto first = pts.begin() + offsets[std::size_t(c)];
      const auto last = pts.begin() + offsets[std::size_t(c) + 1];
      std::sort(first, last, [](const ColumnReturn& a, const ColumnReturn& b) {
        return a.elevation < b.elevation;
      });
      tests.column({first, last}, result.is_ground, feet);
    }
  }
  for (const std::uint32_t i : feet)
    if (result.is_ground[i]) {
      result.is_ground[i] = 0;
      --result.ground_count;
    }
}

// Radial length of the polar cells at range r_m (m).
double cell_length_m(const RobustGroundConfig& config, double r_m) {
  return std::max(config.min_cell_m, config.cell_growth * r_m);
}

// Points bucketed by square 2D cell through a hash of the cell's indices: one counting sort
// into the hash's slots, so that the points of a slot are contiguous. Two cells sharing a slot
// only cost the queries a few more tests.
class CellBuckets {
 public:
  CellBuckets(float cell_m, std::span<const CellPoint> pts) : inv_(1.f / cell_m) {
    std::size_t size = 64;
    while (size < pts.size()) size *= 2;
    mask_ = std::uint32_t(size - 1);
    start_.assign(size + 1, 0);
    std::vector<std::uint32_t> slots(pts.size());
    for (std::size_t k = 0; k < pts.size(); ++k) {
      slots[k] = slot_of(cell(pts[k].x), cell(pts[k].y));
      ++start_[slots[k] + 1];
    }
    for (std::size_t k = 0; k < size; ++k) start_[k + 1] += start_[k];
    pts_.resize(pts.size());
    std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
    for (std::size_t k = 0; k < pts.size(); ++k) pts_[fill[slots[k]]++] = pts[k];
  }
  int cell(float v) const { return int(std::floor(v * inv_)); }
  /// Calls f(q) for the points q of the 3 x 3 cells around cell (ix, iy), and some others,
  /// until f returns false.
  template <class F>
  void around(int ix, int iy, F&& f) const {
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy) {
        const std::uint32_t slot = slot_of(ix + dx, iy + dy);
        for (std::uint32_t k = start_[slot]; k < start_[slot + 1]; ++k)
          if (!f(pts_[k])) return;
      }
  }

 private:
  std::uint32_t slot_of(int ix, int iy) const {
    return ((std::uint32_t(ix) * 73856093u) ^ (std::uint32_t(iy) * 19349663u)) & mask_;
  }
  float inv_;
  std::uint32_t mask_ = 0;
  std::vector<std::uint32_t> start_;
  std::vector<CellPoint> pts_;
};

// Undergrowth test (dense beam tables): a ground return on or above its polar cell's plane and
// under_veg_raised_m or more above the local ground -- the lower quartile of the ground returns
// in the 3 x 3 cells of under_veg_ground_cell_m around it, robust to the litter itself -- with at
// least under_veg_min_returns non-ground returns over it (within under_veg_radius_m
// horizontally, under_veg_raised_m to under_veg_top_m higher) lies in leaf litter, under a
// shrub's skirt or in the low crown of a tree, not on the ground. Ground running on under a
// hedge lies at the ground level and is kept. Only the returns of cells with enough low
// vegetation within reach are tested, and the local ground is found once per ground cell.
void reject_under_vegetation(const PolarGrid& grid, const PolarCells& cells,
                             const std::vector<CellFit>& fits, const RobustGroundConfig& config,
                             GroundResult& result) {
  const float radius = float(config.under_veg_radius_m);
  const float raised = float(config.under_veg_raised_m), top = float(config.under_veg_top_m);
  const std::uint32_t min_returns = std::uint32_t(config.under_veg_min_returns);
  const float low_top = top + float(config.ground_above_m);
  const float above_plane = float(config.under_veg_above_plane_m);
  // Non-ground returns low enough over their cell's ground to be over a ground return.
  std::vector<std::uint32_t> low_in(fits.size(), 0);
  std::vector<CellPoint> low_pts;
  for (std::size_t c = 0; c < fits.size(); ++c) {
    const CellFit& fit = fits[c];
    if (fit.state == CellState::kEmpty) continue;
    const auto pts = cells.points(c);
    const auto idx = cells.members(c);
    for (std::size_t k = 0; k < pts.size(); ++k) {
      if (result.is_ground[idx[k]]) continue;
      if (fit.height_over_ground(pts[k]) < low_top) {
        low_pts.push_back(pts[k]);
        ++low_in[c];
      }
    }
  }
  if (low_pts.size() < min_returns) return;
  const int sectors = grid.sectors(), bins = grid.bins();
  const double sector_rad = 2.0 * std::numbers::pi / sectors;
  // Sectors either way that a distance spans at bin b's inner edge.
  const auto sectors_spanned = [&](int b, double distance_m) {
    const double centre = grid.bin_centre_m(b);
    const double inner = std::max(0.5, centre - 0.5 * cell_length_m(config, centre));
    return std::min(sectors / 2, int(std::ceil(distance_m / (inner * sector_rad))));
  };
  // Calls f(cell) for the cells up to bin_span bins and sector_span sectors from (b, s).
  const auto for_cells_around = [&](int b, int s, int bin_span, int sector_span, auto&& f) {
    for (int db = -bin_span; db <= bin_span; ++db)
      if (b + db >= 0 && b + db < bins)
        for (int ds = -sector_span; ds <= sector_span; ++ds)
          f(grid.cell(b + db, (s + ds + sectors) % sectors));
  };
  // Cells with enough of them within reach: one bin and as many sectors either way as
  // under_veg_radius_m spans.
  std::vector<std::uint8_t> within_reach(fits.size(), 0);
  for (int b = 0; b < bins; ++b) {
    const int span = sectors_spanned(b, radius);
    for (int s = 0; s < sectors; ++s) {
      const std::size_t c = grid.cell(b, s);
      if (fits[c].state == CellState::kEmpty) continue;
      std::uint32_t n = 0;
      for_cells_around(b, s, 1, span, [&](std::size_t cc) { n += low_in[cc]; });
      within_reach[c] = n >= min_returns;
    }
  }
  // Ground returns with enough vegetation over them.
  const CellBuckets low(radius, low_pts);
  const float r2 = radius * radius;
  std::vector<std::size_t> covered;        // positions in `cells`
  std::vector<std::size_t> covered_cells;  // their polar cells, once each
  for (std::size_t c = 0; c < fits.size(); ++c) {
    if (!within_reach[c]) continue;
    const std::size_t before = covered.size();
    const CellFit& fit = fits[c];
    for (std::size_t k = cells.offsets[c]; k < cells.offsets[c + 1]; ++k) {
      if (!result.is_ground[cells.order[k]]) continue;
      const CellPoint& p = cells.xyz[k];
      if (fit.state == CellState::kGround && fit.height_above(p) < above_plane) continue;
      std::uint32_t over = 0;
      low.around(low.cell(p.x), low.cell(p.y), [&](const CellPoint& q) {
        const float dz = q.z - p.z, dx = q.x - p.x, dy = q.y - p.y;
        over += dz > raised && dz < top && dx * dx + dy * dy < r2;
        return over < min_returns;
      });
      if (over >= min_returns) covered.push_back(k);
    }
    if (covered.size() > before) covered_cells.push_back(c);
  }
  if (covered.empty()) return;
  // Their height over the local ground, from the ground returns before any is rejected, once
  // per ground cell: those of the polar cells within two ground cells of a covered return, one in
  // kGroundSample (a quartile of hundreds of returns does not need them all).
  constexpr std::size_t kGroundSample = 4;
  const double ground_reach = 2.0 * config.under_veg_ground_cell_m;
  std::vector<std::uint8_t> near_covered(fits.size(), 0);
  for (const std::size_t c : covered_cells) {
    const int b = int(c % std::size_t(bins)), s = int(c / std::size_t(bins));
    const int bin_span = int(std::ceil(ground_reach / cell_length_m(config, grid.bin_centre_m(b))));
    for_cells_around(b, s, bin_span, sectors_spanned(b, ground_reach),
                     [&](std::size_t cc) { near_covered[cc] = 1; });
  }
  std::vector<CellPoint> ground_pts;
  std::size_t seen = 0;
  for (std::size_t c = 0; c < fits.size(); ++c) {
    if (!near_covered[c]) continue;
    for (std::size_t k = cells.offsets[c]; k < cells.offsets[c + 1]; ++k)
      if (result.is_ground[cells.order[k]] && ++seen % kGroundSample == 0)
        ground_pts.push_back(cells.xyz[k]);
  }
  const CellBuckets ground(float(config.under_veg_ground_cell_m), ground_pts);
  const auto cell_of = [&ground, &cells](std::size_t k) {
    return std::pair{ground.cell(cells.xyz[k].x), ground.cell(cells.xyz[k].y)};
  };
  std::sort(covered.begin(), covered.end(),
            [&](std::size_t a, std::size_t b) { return cell_of(a) < cell_of(b); });
  std::vector<float> zs;
  std::vector<std::uint32_t> rejected;
  float base = 0.f;
  for (std::size_t n = 0; n < covered.size(); ++n) {
    const auto [ix, iy] = cell_of(covered[n]);
    if (n == 0 || cell_of(covered[n - 1]) != std::pair{ix, iy}) {
      zs.clear();
      ground.around(ix, iy, [&](const CellPoint& q) {
        if (std::abs(ground.cell(q.x) - ix) <= 1 && std::abs(ground.cell(q.y) - iy) <= 1)
          zs.push_back(q.z);
        return true;
      });
      // Too few ground returns sampled around to tell: not rejected.
      base = std::numeric_limits<float>::infinity();
      if (!zs.empty()) {
        const auto quartile = zs.begin() + std::ptrdiff_t(zs.size() / 4);
        std::nth_element(zs.begin(), quartile, zs.end());
        base = *quartile;
      }
    }
    if (cells.xyz[covered[n]].z - base >= raised) rejected.push_back(cells.order[covered[n]]);
  }
  for (const std::uint32_t i : rejected) {
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
      const std::size_t c = grid.cell(b, s);
      if (cells.offsets[c] == cells.offsets[c + 1]) continue;
      const CellPoint& low = cells.xyz[cells.lowest[c]];
      if (low.z < 0.f) lows.emplace_back(low.x, low.y, low.z);
    }
  NearGroundPlane prior = fit_plane_to_lows(lows, max_slope_rad);
  if (!prior.found) prior.c = -(sensor.mounting_height_m > 0 ? sensor.mounting_height_m : 1.0);
  result.sensor_height_m = -prior.c / std::sqrt(1.0 + prior.a * prior.a + prior.b * prior.b);

  const float max_cos = float(std::cos(max_slope_rad));
  const double tan_slope = std::tan(max_slope_rad);
  const double tan_bend = std::tan(config.max_bend_deg * std::numbers::pi / 180.0);
  // The line continuation, the pit walls and (by default) the face tests are for sparse beam
  // tables, where a cell often holds a single scan line; on 64 rings the first two cost more
  // than they gain (RELLIS-3D F1 0.9563 -> 0.9553).
  const bool sparse_rings = sensor.rings() <= 32;
  const double tan_line =
      sparse_rings ? std::tan(config.max_line_slope_deg * std::numbers::pi / 180.0) : 0.0;
  std::vector<CellFit> fits(grid.cell_count());

  // Pass 1, per sector from the sensor outward: a cell is ground when its low-point plane is
  // upright and flat and continues the ground of the inner cells (or, before any, the prior).
  for (int s = 0; s < grid.sectors(); ++s) {
    const float a_mid = grid.sector_centre_rad(s);
    const float ca = std::cos(a_mid), sa = std::sin(a_mid);
    bool anchored = false;
    double ref_z = 0.0, ref_r = 0.0, ref_grad = 0.0;
    bool ref_line = false;
    std::size_t ref_cell = 0;
    // Lowest return of the sector farther out than bin b (m): ground seen from the sensor has
    // nothing much lower beyond it in the same direction, unless behind a crest, while a canopy
    // or a hedge top has the ground beyond it.
    const auto lowest_beyond = [&](int b) {
      float z = std::numeric_limits<float>::infinity();
      for (int bb = b + 1; bb < grid.bins(); ++bb) {
        const std::size_t cc = grid.cell(bb, s);
        if (cells.offsets[cc] != cells.offsets[cc + 1])
          z = std::min(z, cells.xyz[cells.lowest[cc]].z);
      }
      return z;
    };
    const auto line_of = [&](std::size_t cc) {
      return line_stats(cells.points(cc), cells.rho.data() + cells.offsets[cc],
                        cells.xyz[cells.lowest[cc]].z + float(config.seed_band_m));
    };
    for (int b = 0; b < grid.bins(); ++b) {
      const std::size_t c = grid.cell(b, s);
      const auto members = cells.points(c);
      if (members.empty()) continue;
      const float r_mid = grid.bin_centre_m(b);
      CellFit& fit = fits[c];
      const PlaneFit plane = fit_cell(members, cells.xyz[cells.lowest[c]].z, config.seed_band_m,
                                      max_cos, r_mid * ca, r_mid * sa, fit);
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
      bool continuous = std::abs(fit.elevation - predicted) <= tolerance;
      // Sparse rings far out: a cell holds one scan line, whose plane's tilt is unknown, and a
      // hillside rises by more than the bend tolerance from one line to the next. A line with
      // nothing above it in its cell continues the ground when it rises from the last ground
      // line, at most line_reach_cells cell lengths nearer (not across a shadow), by no more than
      // max_line_slope_deg and nothing beyond it lies lower; the ground then follows that
      // gradient.
      double line_grad = 0;
      bool by_line = false;
      if (!continuous && anchored && plane.line_only && ref_line && tan_line > 0) {
        const LineStats line = line_of(c);
        const double run = double(line.rho) - line_of(ref_cell).rho;
        const double cell_len = cell_length_m(config, r_mid);
        if (line.alone && run > 0.3 && run <= config.line_reach_cells * cell_len) {
          line_grad = (fit.elevation - ref_z) / run;
          by_line = line_grad >= 0 && line_grad <= tan_line &&
                    lowest_beyond(b) >= fit.elevation - float(config.max_step_m);
          continuous = by_line;
        }
      }
      // Behind a crest: the ground between falls out of sight and reappears lower, at least
      // descent_gap_m beyond the last ground cell. The drop continues the ground when it is no
      // steeper than the steepest ground plane and, for a single scan line, nothing stands on the
      // line in its cell (the top of a bush down the slope). Nearer drops are pits: the chain
      // stays at the rim level to reach the far rim.
      if (!continuous && anchored && fit.elevation < std::min(predicted, ref_z) &&
          r_mid - ref_r >= config.descent_gap_m &&
          ref_z - fit.elevation <= config.max_step_m + tan_slope * (r_mid - ref_r) &&
          (!plane.line_only || line_of(c).alone)) {
        continuous = true;
        fit.predicted = fit.elevation;  // no pit walls above the cell's own plane
      }
      const bool flat = plane.flatness <= config.max_flatness_m;
      if (continuous && plane.upright && flat) {
        fit.state = CellState::kGround;
        anchored = true;
        ref_z = fit.elevation;
        ref_r = r_mid;
        ref_line = plane.line_only;
        ref_cell = c;
        // Radial gradient of the cell's plane, to follow a hill outward.
        const double g = -(plane.normal.x() * ca + plane.normal.y() * sa) / plane.normal.z();
        ref_grad = by_line ? line_grad : std::clamp(g, -tan_slope, tan_slope);
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
  const float rim_above = sparse_rings ? float(config.rim_above_m) : -1.f;
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
    // A pit or ditch whose bottom holds the cell's low points: its walls and rim, up to the
    // ground expected from the inner cells, are ground however far above the bottom.
    const bool pit_walls = fit.state == CellState::kGround && rim_above >= 0;
    const auto pts = cells.points(c);
    const auto idx = cells.members(c);
    for (std::size_t k = 0; k < pts.size(); ++k) {
      const CellPoint& p = pts[k];
      const std::uint32_t i = idx[k];
      const float h = fit.height_over_ground(p);
      if (h >= -below && (h <= cell_above || (pit_walls && p.z - fit.predicted <= rim_above))) {
        result.is_ground[i] = 1;
        ++result.ground_count;
      }
    }
  }
  // Dense beam tables (64+ rings) resolve the faces themselves in the plane fits and gain
  // nothing measurable from the test (RELLIS-3D: F1 0.9563 either way), at 2-3x the cost.
  const int face_columns = config.face_columns >= 0 ? config.face_columns
                           : sparse_rings           ? sensor.columns
                                                    : 0;

  if (face_columns > 0)
    reject_face_feet(grid, cells, config, std::min(face_columns, 1 << 16),
                     cloud.fields.ring ? int(sensor.rings()) : 0, result);
  // The undergrowth test needs the returns of a dense beam table over the litter (and costs
  // more than a sparse one's whole segmentation).
  if (!sparse_rings && config.under_veg_min_returns > 0)
    reject_under_vegetation(grid, cells, fits, config, result);

  return result;
}

}  // namespace fieldlidar::segmentation
