#include "support/follow_replay_picture.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "fieldlidar/follow/replay.hpp"
#include "support/canvas.hpp"

namespace fieldlidar::app {

namespace {

Rgb replay_state_colour(follow::FollowState s) {
  switch (s) {
    case follow::FollowState::kFollowing:
      return {0.15, 0.35, 0.9};
    case follow::FollowState::kTooClose:
      return {0.95, 0.55, 0.1};
    case follow::FollowState::kTooFar:
      return {0.6, 0.2, 0.7};
    case follow::FollowState::kLost:
      return {0.85, 0.1, 0.1};
    case follow::FollowState::kIdle:
      break;
  }
  return {0.6, 0.6, 0.6};
}

/// The state of a log row as the replay's summary counts it.
follow::FollowState replay_state(const loops::LogRow& r) {
  return follow::counted_state(r.target_id >= 0, r.state);
}

}  // namespace

void write_follow_replay_picture(const std::filesystem::path& path,
                                 std::span<const loops::LogRow> rows, double gap_s,
                                 const std::string& title, bool overwrite) {
  // The area: the mower's path and every target estimate, at least 4 m across.
  Eigen::Vector2d lo(0, 0), hi(0, 0);
  bool first = true;
  auto extend = [&](double x, double y) {
    if (!std::isfinite(x) || !std::isfinite(y)) return;
    const Eigen::Vector2d p(x, y);
    lo = first ? p : lo.cwiseMin(p);
    hi = first ? p : hi.cwiseMax(p);
    first = false;
  };
  for (const auto& r : rows) {
    extend(r.mower_x, r.mower_y);
    extend(r.est_x, r.est_y);
  }
  const Eigen::Vector2d centre = 0.5 * (lo + hi);
  const Eigen::Vector2d half = (0.5 * (hi - lo)).cwiseMax(2.0) + Eigen::Vector2d(1.0, 1.0);
  lo = centre - half;
  hi = centre + half;
  // The timeline strip below the area: one column per scan across its width.
  const double strip_h = 0.06 * (hi.y() - lo.y()), strip_top = lo.y() - 0.6 * strip_h;
  const double strip_bottom = strip_top - strip_h;
  TopDownCanvas canvas({lo.x(), strip_bottom - 1.2 * strip_h}, hi, 1200);
  const double width_m = hi.x() - lo.x();
  const double column_px =
      canvas.pixels_per_metre() * width_m / double(std::max<std::size_t>(1, rows.size()));
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const double x = lo.x() + width_m * (double(i) + 0.5) / double(rows.size());
    const std::vector<Eigen::Vector2d> column{{x, strip_bottom}, {x, strip_top}};
    canvas.polyline(column, replay_state_colour(replay_state(rows[i])), std::max(1.0, column_px));
    if (i > 0 && rows[i].t_s - rows[i - 1].t_s > gap_s) {
      const double xb = lo.x() + width_m * double(i) / double(rows.size());
      const std::vector<Eigen::Vector2d> tick{{xb, strip_bottom - 0.3 * strip_h},
                                              {xb, strip_top + 0.3 * strip_h}};
      canvas.polyline(tick, {0, 0, 0}, 2.0);
    }
  }
  canvas.text({lo.x(), strip_bottom - 0.9 * strip_h},
              "state per scan, first to last (black ticks: breaks in the recording)");

  std::vector<Eigen::Vector2d> mower;
  for (const auto& r : rows) mower.emplace_back(r.mower_x, r.mower_y);
  canvas.polyline(mower, {0.1, 0.1, 0.1}, 1.5);
  for (const auto& r : rows)
    if (std::isfinite(r.est_x) && std::isfinite(r.est_y))
      canvas.dot({r.est_x, r.est_y}, replay_state_colour(replay_state(r)), 2.5);
  if (!rows.empty())
    canvas.arrow({rows.front().mower_x, rows.front().mower_y}, rows.front().mower_yaw, 0.8,
                 {0, 0, 0});
  canvas.legend(
      {{"mower path (arrow: start)", {0.1, 0.1, 0.1}},
       {"target, following", replay_state_colour(follow::FollowState::kFollowing)},
       {"target, too close (stopped)", replay_state_colour(follow::FollowState::kTooClose)},
       {"target, too far (stopped)", replay_state_colour(follow::FollowState::kTooFar)},
       {"lost (stopped)", replay_state_colour(follow::FollowState::kLost)},
       {"no target yet", replay_state_colour(follow::FollowState::kIdle)}});
  canvas.title(title);
  canvas.save_png(path, overwrite);
}

}  // namespace fieldlidar::app
