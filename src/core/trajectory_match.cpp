#include "fieldlidar/core/trajectory_match.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "fieldlidar/core/error.hpp"

namespace fieldlidar {

MatchedPoses match_by_time(const Trajectory& a, const Trajectory& b, double max_dt_s) {
  // A NaN gate fails no `best > max_dt_s` test: every pose would be paired, however far apart.
  if (!(max_dt_s >= 0.0))
    throw Error("time matching: max dt " + std::to_string(max_dt_s) + " s is not a number >= 0");
  MatchedPoses m;
  const auto& pb = b.poses();
  std::size_t next_b = 0;  // first pose of b not yet used (pairs keep both orders)
  for (std::size_t i = 0; i < a.size(); ++i) {
    const double t = a[i].stamp_s;
    const auto it = std::lower_bound(pb.begin() + static_cast<std::ptrdiff_t>(next_b), pb.end(), t,
                                     [](const StampedPose& p, double s) { return p.stamp_s < s; });
    auto j = static_cast<std::size_t>(it - pb.begin());
    double best = std::numeric_limits<double>::infinity();
    std::size_t best_j = pb.size();
    for (std::size_t k : {j - 1, j}) {  // the neighbours before and after t (j - 1 may wrap)
      if (k < next_b || k >= pb.size()) continue;
      const double dt = std::abs(pb[k].stamp_s - t);
      if (dt < best) {
        best = dt;
        best_j = k;
      }
    }
    if (best_j == pb.size() || best > max_dt_s) continue;
    m.a.push_back(a[i].pose);
    m.b.push_back(pb[best_j].pose);
    m.indices.emplace_back(i, best_j);
    m.max_dt_s = std::max(m.max_dt_s, best);
    next_b = best_j + 1;
  }
  return m;
}

}  // namespace fieldlidar
