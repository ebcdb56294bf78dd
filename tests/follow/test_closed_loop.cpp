#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "fieldlidar/follow/closed_loop.hpp"

namespace fieldlidar::follow {
namespace {

ClosedLoopResult run(Scenario s) {
  const auto scene = sim::make_lawn_scene(lawn_config(s), 0);
  ClosedLoopConfig cfg;
  auto r = run_closed_loop(scene, SensorModel::vlp16(), cfg);
  std::printf(
      "%s: frames %zu following %zu stopped_by_command %d duration %.1f s boundary mean %.3f m "
      "hausdorff %.3f m vertices %zu self-x %zu too_close_moving %zu switches %zu off %zu "
      "occlusions %zu stop_delay %d resume_delay %d perception %.2f ms\n",
      to_string(s).c_str(), r.rows.size(), r.frames_following, int(r.stopped_by_command),
      r.duration_s, r.boundary_error.mean_m, r.boundary_error.hausdorff_m,
      r.boundary.vertices.size(), r.boundary.self_intersections.size(), r.frames_moving_too_close,
      r.target_switches, r.frames_target_off, r.occlusions, r.max_stop_delay_frames,
      r.max_resume_delay_frames, r.mean_perception_ms);
  if (const char* dir = std::getenv("FIELDLIDAR_FOLLOW_DUMP")) {
    if (FILE* f = std::fopen((std::string(dir) + "/" + to_string(s) + ".csv").c_str(), "w")) {
      std::fputs(log_csv(r.rows).c_str(), f);
      std::fclose(f);
    }
  }
  return r;
}

TEST(ClosedLoop, DefaultLawnBoundaryMatchesTheWalkedLoop) {
  const auto r = run(Scenario::kDefault);
  EXPECT_TRUE(r.stopped_by_command);
  EXPECT_LE(r.boundary_error.mean_m, 0.10);
  EXPECT_LE(r.boundary_error.hausdorff_m, 0.30);
  EXPECT_EQ(r.frames_moving_too_close, 0u);
  EXPECT_EQ(r.target_switches, 0u);
  EXPECT_TRUE(r.boundary.self_intersections.empty());
}

}  // namespace
}  // namespace fieldlidar::follow
namespace fieldlidar::follow {
namespace {
TEST(ClosedLoopScan, Others) {
  for (auto s : {Scenario::kCrossing, Scenario::kStop, Scenario::kFast, Scenario::kOccluded})
    run(s);
}
}  // namespace
}  // namespace fieldlidar::follow
