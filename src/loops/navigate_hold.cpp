// The navigate loop's detour hold: a plan blocked far ahead is kept up to a point short of the
// block while the map is updated, rather than swapped at once for a much longer detour.

#include <algorithm>
#include <cmath>
#include <limits>

#include "fieldlidar/loops/navigate_maps.hpp"
#include "fieldlidar/planning/path_check.hpp"
#include "navigate_loop.hpp"

namespace fieldlidar::loops::detail {

namespace {

double step_m(const planning::Path& path, std::size_t i) {
  return std::hypot(path[i].pose.x_m - path[i - 1].pose.x_m,
                    path[i].pose.y_m - path[i - 1].pose.y_m);
}

}  // namespace

Loop::HeldRest Loop::held_rest() const {
  HeldRest r;
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < held_.size(); ++i) {
    const double d = std::hypot(held_[i].pose.x_m - me().x_m, held_[i].pose.y_m - me().y_m);
    if (d < best) best = d, r.from = i;
  }
  r.blocked = planning::first_blocked_sample(*check_map_, held_, r.from);
  for (std::size_t i = r.from + 1; i < held_.size(); ++i) {
    r.to_end_m += step_m(held_, i);
    if (!r.blocked || i <= *r.blocked) r.to_block_m = r.to_end_m;
  }
  return r;
}

bool Loop::follow_held(std::size_t from, std::optional<std::size_t> block) {
  std::size_t end = held_.size() - 1;
  if (block) {
    // Up to hold_stop_m before the block, and only over ground the map knows: an unknown cell
    // short of the block may be its unseen part (a ditch's inside, a shadow), which driving
    // nearer would reach first.
    end = *block;
    const auto tau = grid_.layer(terrain::layer::kTraversability);
    for (std::size_t i = from; i < *block && end == *block; ++i)
      for (long c : footprint_cells(area_, held_[i].pose, robot_))
        if (c < 0 || !std::isfinite(tau[std::size_t(c)])) {
          end = i;
          break;
        }
    for (double back = 0; end > from && back < cfg_.hold_stop_m; --end) back += step_m(held_, end);
    double ahead = 0;
    for (std::size_t i = from + 1; i <= end; ++i) ahead += step_m(held_, i);
    if (ahead < cfg_.hold_min_ahead_m) return false;
  }
  if (end < from + 3) return false;
  planning::Path rest(held_.begin() + long(from), held_.begin() + long(end) + 1);
  step_costs_ = step_costs(rest);
  follower_.set_path(std::move(rest));
  state_ = NavigateState::kDriving;
  return true;
}

bool Loop::hold_before_plan(const std::string& trigger) {
  if (trigger == "blocked" && held_.empty() && cfg_.detour_hold_ratio > 0 && follower_.has_path()) {
    held_ = follower_.path();  // a candidate: hold_instead_of decides
    return false;
  }
  if (held_.empty()) return false;
  if (trigger != "hold") {  // a safety stop, a time-out: the hold ends
    held_.clear();
    return false;
  }
  const HeldRest r = held_rest();
  if (!r.blocked) {  // the block cleared: the held plan goes on
    const bool ok = follow_held(r.from, std::nullopt);
    held_.clear();
    return ok;
  }
  return false;  // still blocked: plan, then hold_instead_of compares
}

bool Loop::hold_instead_of(double length_m) {
  if (held_.empty()) return false;
  const HeldRest r = held_rest();
  const bool hold =
      r.blocked && length_m > cfg_.detour_hold_ratio * r.to_end_m && follow_held(r.from, r.blocked);
  if (!hold) held_.clear();
  return hold;
}

}  // namespace fieldlidar::loops::detail
