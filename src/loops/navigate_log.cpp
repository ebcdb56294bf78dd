// The navigate loop's default map and planner settings, names and its CSV log.

#include <fmt/core.h>

#include "fieldlidar/loops/navigate.hpp"

namespace fieldlidar::loops {

planning::PlannerConfig navigate_planner_config() {
  planning::PlannerConfig c;
  c.map.unknown_tau = 1.0;
  // Searches are not hurried in the loop: it re-plans every few seconds on a small map, and its
  // driven paths grew with it (scripts/navigate_seeds.py 2 21: mean length ratio 1.050 -> 1.073
  // at 500 expansions, 1.058 at 700, 1.055 at 1000; 180 -> 178-179 of 184 arriving).
  c.late_expansions = 0;
  return c;
}

terrain::FusionConfig navigate_fusion_config() {
  terrain::FusionConfig c;
  c.layers.ground.levelling.enabled = false;
  return c;
}

const char* to_string(NavigateOutcome outcome) {
  switch (outcome) {
    case NavigateOutcome::kArrived:
      return "arrived";
    case NavigateOutcome::kUnreachable:
      return "unreachable";
    case NavigateOutcome::kFailed:
      return "failed";
  }
  return "?";
}

const char* to_string(NavigateState state) {
  switch (state) {
    case NavigateState::kPlanning:
      return "planning";
    case NavigateState::kDriving:
      return "driving";
    case NavigateState::kSafetyStop:
      return "safety_stop";
    case NavigateState::kArrived:
      return "arrived";
    case NavigateState::kUnreachable:
      return "unreachable";
    case NavigateState::kFailed:
      return "failed";
  }
  return "?";
}

std::string navigate_log_csv(const std::vector<NavigateLogRow>& rows) {
  std::string s =
      "t_s,x_m,y_m,yaw_rad,v_m_s,yaw_rate_rad_s,planned_length_m,cell_ix,cell_iy,"
      "cell_passable_truth,footprint_on_impassable,impassable_depth_m,obstacle_gap_m,tilt_deg,"
      "state,replans\n";
  for (const auto& r : rows)
    s += fmt::format(
        "{:.2f},{:.4f},{:.4f},{:.5f},{:.3f},{:.4f},{:.2f},{},{},{},{},{:.2f},{:.2f},{:.1f},{},{}\n",
        r.t_s, r.x_m, r.y_m, r.yaw_rad, r.v_m_s, r.yaw_rate_rad_s, r.planned_length_m, r.cell_ix,
        r.cell_iy, r.cell_passable, int(r.footprint_on_impassable), r.impassable_depth_m,
        r.obstacle_gap_m, r.tilt_deg, to_string(r.state), r.replans);
  return s;
}

}  // namespace fieldlidar::loops
