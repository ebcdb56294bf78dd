// The silhouette's two edges as straight lines through the column intervals of every scan line
// (a set-membership fit: the columns quantise azimuth, nothing else does).
#include "edge_fit.hpp"

#include <algorithm>
#include <cmath>

namespace fieldlidar::forest {
namespace {

// For one slope b: the intervals of the edges' offsets a_lo and a_hi that keep every line.
struct Intervals {
  double lo_min = -1e30, lo_max = 1e30, hi_min = -1e30, hi_max = 1e30;
  double room() const { return std::min(lo_max - lo_min, hi_max - hi_min); }
};

Intervals intervals(std::span<const EdgeLine> lines, double b) {
  Intervals v;
  for (const auto& l : lines) {
    const double shift = b * l.dz_m;
    v.lo_max = std::min(v.lo_max, l.lo_rad - shift);
    v.hi_min = std::max(v.hi_min, l.hi_rad - shift);
    v.lo_min = std::max(v.lo_min, l.lo_out_rad - shift);
    v.hi_max = std::min(v.hi_max, l.hi_out_rad - shift);
  }
  return v;
}

}  // namespace

EdgeWidth fit_edge_width(std::span<const EdgeLine> lines, double max_slope_rad_per_m) {
  EdgeWidth out;
  const bool lo_closed = std::any_of(lines.begin(), lines.end(),
                                     [](const EdgeLine& l) { return l.lo_out_rad > -1e29; });
  const bool hi_closed = std::any_of(lines.begin(), lines.end(),
                                     [](const EdgeLine& l) { return l.hi_out_rad < 1e29; });
  if (!lo_closed || !hi_closed) return out;
  // room(b) is concave (a min of mins less a max of lines): golden section finds its peak.
  const double phi = (std::sqrt(5.0) - 1) / 2;
  double x0 = -max_slope_rad_per_m, x1 = max_slope_rad_per_m;
  double p = x1 - phi * (x1 - x0), q = x0 + phi * (x1 - x0);
  double fp = intervals(lines, p).room(), fq = intervals(lines, q).room();
  for (int it = 0; it < 60; ++it) {
    if (fp < fq) {
      x0 = p, p = q, fp = fq;
      q = x0 + phi * (x1 - x0);
      fq = intervals(lines, q).room();
    } else {
      x1 = q, q = p, fq = fp;
      p = x1 - phi * (x1 - x0);
      fp = intervals(lines, p).room();
    }
  }
  const double peak = (x0 + x1) / 2;
  if (!(intervals(lines, peak).room() > 0)) return out;
  // The feasible slopes: an interval around the peak, its ends by bisection.
  auto end = [&](double outer) {
    double in = peak, o = outer;
    if (intervals(lines, o).room() > 0) return o;
    for (int it = 0; it < 50; ++it) {
      const double m = (in + o) / 2;
      (intervals(lines, m).room() > 0 ? in : o) = m;
    }
    return in;
  };
  const double b0 = end(-max_slope_rad_per_m), b1 = end(max_slope_rad_per_m);
  // Mean width over the feasible set, uniform in (a_lo, a_hi, b).
  constexpr int kSamples = 64;
  double sw = 0, swx = 0;
  out.min_rad = 1e30;
  out.max_rad = -1e30;
  for (int k = 0; k < kSamples; ++k) {
    const double b = b0 + (b1 - b0) * (k + 0.5) / kSamples;
    const Intervals v = intervals(lines, b);
    if (!(v.room() > 0)) continue;
    const double w = (v.lo_max - v.lo_min) * (v.hi_max - v.hi_min);
    sw += w;
    swx += w * ((v.hi_min + v.hi_max) / 2 - (v.lo_min + v.lo_max) / 2);
    out.min_rad = std::min(out.min_rad, v.hi_min - v.lo_max);
    out.max_rad = std::max(out.max_rad, v.hi_max - v.lo_min);
  }
  if (!(sw > 0)) return out;
  out.width_rad = swx / sw;
  out.ok = true;
  return out;
}

}  // namespace fieldlidar::forest
