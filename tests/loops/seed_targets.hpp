#pragma once
// The seed 000 follow targets every lawn lap must meet, whatever the scenario: the recorded
// boundary within 0.10 m on average and 0.30 m at worst of the walked loop, closed by the stop
// command, never moving nearer than L_s, one target throughout and a simple polygon.

#include <gtest/gtest.h>

#include "fieldlidar/loops/closed_loop.hpp"

namespace fieldlidar::loops::test {

inline void expect_seed_000_lap_targets(const ClosedLoopResult& r) {
  EXPECT_TRUE(r.stopped_by_command);
  EXPECT_LE(r.boundary_error.mean_m, 0.10);
  EXPECT_LE(r.boundary_error.hausdorff_m, 0.30);
  EXPECT_EQ(r.frames_moving_too_close, 0u);
  EXPECT_EQ(r.target_switches, 0u);
  EXPECT_EQ(r.frames_target_off, 0u);
  EXPECT_TRUE(r.boundary.self_intersections.empty());
}

}  // namespace fieldlidar::loops::test
