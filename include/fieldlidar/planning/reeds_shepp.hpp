#pragma once
/// \file Reeds–Shepp curves (shortest paths of a car that drives forwards and backwards at a
/// minimum turning radius), computed by OMPL's ReedsSheppStateSpace behind a small wrapper.

#include <array>

#include "fieldlidar/planning/pose2.hpp"

namespace fieldlidar::planning {

/// One piece of a Reeds–Shepp curve: a left arc, a straight, or a right arc, of signed length
/// (m; negative when driven in reverse).
struct RsSegment {
  enum class Kind { kNone, kLeft, kStraight, kRight };
  Kind kind = Kind::kNone;
  double length_m = 0.0;
};

/// The shortest Reeds–Shepp curve between two poses (at most five segments).
struct RsCurve {
  std::array<RsSegment, 5> segments{};
  double length_m = 0.0;  ///< sum of |segment lengths|
};

/// The shortest curve from `from` to `to` at turning radius `radius_m` (> 0).
RsCurve reeds_shepp(const Pose2& from, const Pose2& to, double radius_m);

/// Its length (m) alone.
double reeds_shepp_length_m(const Pose2& from, const Pose2& to, double radius_m);

/// An upper bound of reeds_shepp_length_m at a fraction of its cost: the shortest of the
/// turn-straight-turn curves with both turns the same way, forwards or backwards (four of the
/// 48 Reeds–Shepp words), which are Reeds–Shepp curves themselves.
double reeds_shepp_upper_bound_m(const Pose2& from, const Pose2& to, double radius_m);

/// The pose reached after driving `s_m` (0 <= s_m <= curve.length_m) along the curve from `from`.
Pose2 rs_pose_at(const Pose2& from, const RsCurve& curve, double radius_m, double s_m);

/// The curve sampled at most `step_m` apart, from `from` (first sample) to its end (last), each
/// sample flagged reverse when the segment leading to it is driven backwards.
Path rs_sample(const Pose2& from, const RsCurve& curve, double radius_m, double step_m);

}  // namespace fieldlidar::planning
