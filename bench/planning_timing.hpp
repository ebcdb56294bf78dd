#pragma once
// What the planning benchmarks share: this thread's CPU time and a percentile of plan times.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include <time.h>

namespace fieldlidar::bench {

/// This thread's CPU time (ms): a plan's cost on one core, whatever else the machine runs.
inline double thread_cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}

/// The p-quantile (0..1, nearest rank) of `v`; NaN when it is empty.
inline double percentile(std::vector<double> v, double p) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, std::size_t(p * (v.size() - 1) + 0.5))];
}

}  // namespace fieldlidar::bench
