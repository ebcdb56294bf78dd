#pragma once
// The standing-start scenario read from the closed loop's log: the target chosen while the
// operator stands, the mower waiting, and its first motion after the operator's first step.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "fieldlidar/loops/closed_loop.hpp"

namespace fieldlidar::loops::standing_start {

constexpr double kWaitS = 5.0;  // sim::LawnConfig::wait_at_start_s

/// The standing phase and the walk-off, as read from the log.
struct StandingStart {
  double target_chosen_s = NAN;       ///< first sweep with a target
  double target_error_m = NAN;        ///< its estimate against the operator's true position then
  double worst_standing_error_m = 0;  ///< estimate vs truth over the standing sweeps with a target
  std::size_t standing_sweeps_moving = 0;  ///< wheels turning before the first step
  double standing_travel_m = 0;            ///< how far the mower moved before the first step
  double nearest_standing_m = 1e9;         ///< nearest true distance while standing
  double first_motion_s = NAN;             ///< first sweep after the first step with wheels turning
  std::size_t standing_sweeps_two_people = 0;  ///< sweeps where the posts pass as a person too
};

inline StandingStart read_standing_start(const ClosedLoopResult& r) {
  StandingStart s;
  if (r.rows.empty()) return s;
  const Eigen::Vector2d start(r.rows.front().mower_x, r.rows.front().mower_y);
  for (const auto& row : r.rows) {
    const bool moving = row.wheel_left != 0.0 || row.wheel_right != 0.0;
    const double error = std::hypot(row.est_x - row.true_x, row.est_y - row.true_y);
    if (row.target_id >= 0 && std::isnan(s.target_chosen_s)) {
      s.target_chosen_s = row.t_s;
      s.target_error_m = error;
    }
    if (row.t_s <= kWaitS) {
      s.standing_sweeps_moving += moving;
      s.standing_travel_m =
          std::max(s.standing_travel_m, (Eigen::Vector2d(row.mower_x, row.mower_y) - start).norm());
      s.nearest_standing_m = std::min(s.nearest_standing_m, row.true_distance_m);
      s.standing_sweeps_two_people += row.people_detected >= 2;
      if (row.target_id >= 0) s.worst_standing_error_m = std::max(s.worst_standing_error_m, error);
    } else if (moving && std::isnan(s.first_motion_s)) {
      s.first_motion_s = row.t_s;
    }
  }
  return s;
}

inline void print(const char* what, const ClosedLoopResult& r, const StandingStart& s) {
  std::printf(
      "%s: target chosen at %.2f s (%.3f m off the operator, worst while standing %.3f m), "
      "sweeps with >= 2 people detected while standing %zu, moving sweeps while standing %zu, "
      "travel %.3f m, nearest %.2f m, first motion %.2f s "
      "(%.2f s after the first step); frames %zu following %zu stopped_by_command %d boundary "
      "mean %.3f m hausdorff %.3f m too_close_moving %zu switches %zu off %zu\n",
      what, s.target_chosen_s, s.target_error_m, s.worst_standing_error_m,
      s.standing_sweeps_two_people, s.standing_sweeps_moving, s.standing_travel_m,
      s.nearest_standing_m, s.first_motion_s, s.first_motion_s - kWaitS, r.rows.size(),
      r.frames_following, int(r.stopped_by_command), r.boundary_error.mean_m,
      r.boundary_error.hausdorff_m, r.frames_moving_too_close, r.target_switches,
      r.frames_target_off);
}

inline void expect_standing_start(const StandingStart& s) {
  // The posts beside the operator's start pass as a person (the choice is what is tested).
  EXPECT_GT(s.standing_sweeps_two_people, 25u);
  EXPECT_LT(s.target_chosen_s, kWaitS);  // chosen while the operator stands
  EXPECT_LT(s.target_error_m, 0.3);      // on the operator, not on clutter
  EXPECT_LT(s.worst_standing_error_m, 0.3);
  EXPECT_EQ(s.standing_sweeps_moving, 0u);  // the mower waits
  EXPECT_LT(s.standing_travel_m, 0.01);
  EXPECT_GT(s.nearest_standing_m, ClosedLoopConfig{}.follow.safety.safe_distance_m);
  EXPECT_GT(s.first_motion_s, kWaitS);
  EXPECT_LE(s.first_motion_s - kWaitS, 1.0);  // follows from the first step
}

}  // namespace fieldlidar::loops::standing_start
