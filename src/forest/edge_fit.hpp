#pragma once
// A stem's angular width from the edges of its silhouette across many scan lines: each edge a
// straight line in (height, azimuth) through every line's column interval.
#include <cstddef>
#include <limits>
#include <span>

namespace fieldlidar::forest {

/// What one scan line shows of a stem at height dz (m, from the height the width is wanted at):
/// the azimuths (rad, from any common reference) of its outermost returns, lo and hi, and of the
/// nearest columns beyond them whose beams passed the stem, lo_out < lo and hi_out > hi (the
/// next columns when the edges are free; farther when an occluder hides them; -inf / +inf when
/// nothing beyond is known to pass).
struct EdgeLine {
  double dz_m = 0.0;
  double lo_rad = 0.0, hi_rad = 0.0;
  double lo_out_rad = -1e30, hi_out_rad = 1e30;
};

struct EdgeWidth {
  double width_rad = std::numeric_limits<double>::quiet_NaN();  ///< mean over the feasible set
  double min_rad = 0.0, max_rad = 0.0;                          ///< its bounds
  bool ok = false;  ///< false: an edge with no outer bound on any line, or no straight edges fit
};

/// The two edges are lines e(z) = a + b z with one slope b (|b| <= max_slope_rad_per_m; taper
/// is below a column over a metre). A line puts the low edge in (lo_out, lo] and the high edge
/// in [hi, hi_out). The width at dz = 0 is
/// the mean of e_hi(0) - e_lo(0) over every (a_lo, a_hi, b) that keeps all lines, so lines that
/// cross the stem at different phases of the column step (a leaning stem, a tilted sensor) pin
/// the edges to a fraction of a step.
EdgeWidth fit_edge_width(std::span<const EdgeLine> lines, double max_slope_rad_per_m);

}  // namespace fieldlidar::forest
