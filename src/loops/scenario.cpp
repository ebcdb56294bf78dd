// The closed loop's scenarios on the lawn scene and its log as CSV.

#include <cstdio>

#include "fieldlidar/loops/closed_loop.hpp"

namespace fieldlidar::loops {

std::string to_string(Scenario s) {
  switch (s) {
    case Scenario::kDefault:
      return "default";
    case Scenario::kCrossing:
      return "crossing";
    case Scenario::kStop:
      return "stop";
    case Scenario::kFast:
      return "fast";
    case Scenario::kOccluded:
      return "occluded";
    case Scenario::kStandingStart:
      return "standing-start";
    case Scenario::kRough:
      return "rough";
  }
  return "default";
}

std::optional<Scenario> scenario_from_string(const std::string& n) {
  for (auto s : {Scenario::kDefault, Scenario::kCrossing, Scenario::kStop, Scenario::kFast,
                 Scenario::kOccluded, Scenario::kStandingStart, Scenario::kRough})
    if (to_string(s) == n) return s;
  return std::nullopt;
}

sim::LawnConfig lawn_config(Scenario s) {
  sim::LawnConfig c;
  c.second_person_crossing = s == Scenario::kCrossing;
  c.operator_stops = s == Scenario::kStop;
  c.operator_too_fast = s == Scenario::kFast;
  c.operator_behind_shed = s == Scenario::kOccluded;
  if (s == Scenario::kRough) c.roughness_m = 0.06;  // tussocks and ruts: the mower pitches ~5 deg
  if (s == Scenario::kStandingStart) {
    // Within the follow distance, so that the mower has no reason to move before the first step.
    c.operator_waits_at_start = true;
    c.operator_start_m = 2.0;
    c.posts_near_start = true;  // leg-like clutter nearer than the operator
  }
  return c;
}

std::string log_csv(const std::vector<LogRow>& rows) {
  std::string s =
      "t,mower_x,mower_y,mower_yaw,est_x,est_y,true_target_x,true_target_y,distance,"
      "true_distance,wheel_left,wheel_right,state,target_id,target_points,people_detected,"
      "mower_est_x,mower_est_y,mower_est_yaw\n";
  char buf[512];
  for (const auto& r : rows) {
    std::snprintf(buf, sizeof buf,
                  "%.3f,%.4f,%.4f,%.5f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%s,%lld,%u,%zu,"
                  "%.4f,%.4f,%.5f\n",
                  r.t_s, r.mower_x, r.mower_y, r.mower_yaw, r.est_x, r.est_y, r.true_x, r.true_y,
                  r.distance_m, r.true_distance_m, r.wheel_left, r.wheel_right,
                  to_string(r.state).c_str(), static_cast<long long>(r.target_id), r.target_points,
                  r.people_detected, r.mower_est_x, r.mower_est_y, r.mower_est_yaw);
    s += buf;
  }
  return s;
}

}  // namespace fieldlidar::loops
