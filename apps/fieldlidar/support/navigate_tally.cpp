#include "navigate_tally.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/core.h>

namespace fieldlidar::app {

void NavigateTally::add(const loops::NavigateResult& r) {
  ++pairs_;
  touching_ += r.frames_on_impassable > 0;
  frames_ += r.frames_on_impassable;
  deep_ += r.max_impassable_depth_m >= kDeep_m;
  contact_ += r.frames_on_obstacles > 0;
  if (r.truth_status != planning::PlanStatus::kSuccess) {
    ++unreachable_;
    said_unreachable_ += r.outcome == loops::NavigateOutcome::kUnreachable;
    return;
  }
  ++reachable_;
  if (r.outcome != loops::NavigateOutcome::kArrived || !std::isfinite(r.length_ratio)) return;
  ++arrived_;
  within_ += r.length_ratio <= ratio_bound_;
  ratio_sum_ += r.length_ratio;
  ratio_max_ = std::max(ratio_max_, r.length_ratio);
}

std::string NavigateTally::text() const {
  std::string s = fmt::format("{} pairs: {} of {} goals the truth plan reaches arrived", pairs_,
                              arrived_, reachable_);
  if (arrived_ > 0)
    s += fmt::format(" ({} within {:.2f} x its length, mean {:.3f}, largest {:.3f})", within_,
                     ratio_bound_, ratio_sum_ / double(arrived_), ratio_max_);
  s += fmt::format(
      "; {} drives with the footprint on truth-impassable cells ({} frames; {} reaching {:.2f} m "
      "or more into such a cell; {} meeting an obstacle itself)",
      touching_, frames_, deep_, kDeep_m, contact_);
  s += fmt::format("; {} of {} goals it cannot reach reported unreachable", said_unreachable_,
                   unreachable_);
  return s;
}

}  // namespace fieldlidar::app
