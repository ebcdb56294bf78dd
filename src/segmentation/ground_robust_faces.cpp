// Foot-of-a-face test of the robust ground: the returns of one azimuth column ordered by
// elevation are, to the column's width, the beams of neighbouring rings; a steep pair of them
// lies on a vertical face.

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "ground_robust_cells.hpp"

namespace fieldlidar::segmentation::detail {
namespace {

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

}  // namespace

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

}  // namespace fieldlidar::segmentation::detail
