// Reeds–Shepp curves from OMPL (ReedsSheppStateSpace solves all 48 words); sampling of a curve
// is the closed-form integration of its arcs and straights, scaled by the turning radius.

#include "fieldlidar/planning/reeds_shepp.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <ompl/base/ScopedState.h>
#include <ompl/base/spaces/ReedsSheppStateSpace.h>

namespace fieldlidar::planning {
namespace {

namespace ob = ompl::base;

RsSegment::Kind kind_of(ob::ReedsSheppStateSpace::ReedsSheppPathSegmentType t) {
  switch (t) {
    case ob::ReedsSheppStateSpace::RS_LEFT:
      return RsSegment::Kind::kLeft;
    case ob::ReedsSheppStateSpace::RS_STRAIGHT:
      return RsSegment::Kind::kStraight;
    case ob::ReedsSheppStateSpace::RS_RIGHT:
      return RsSegment::Kind::kRight;
    default:
      return RsSegment::Kind::kNone;
  }
}

// Pose after driving signed length v (m) on one segment.
Pose2 advance(const Pose2& p, RsSegment::Kind kind, double v_m, double radius_m) {
  const double phi = p.yaw_rad;
  const double a = v_m / radius_m;
  switch (kind) {
    case RsSegment::Kind::kLeft:
      return {p.x_m + radius_m * (std::sin(phi + a) - std::sin(phi)),
              p.y_m - radius_m * (std::cos(phi + a) - std::cos(phi)), wrap_angle(phi + a)};
    case RsSegment::Kind::kRight:
      return {p.x_m - radius_m * (std::sin(phi - a) - std::sin(phi)),
              p.y_m + radius_m * (std::cos(phi - a) - std::cos(phi)), wrap_angle(phi - a)};
    case RsSegment::Kind::kStraight:
      return {p.x_m + v_m * std::cos(phi), p.y_m + v_m * std::sin(phi), phi};
    default:
      return p;
  }
}

}  // namespace

RsCurve reeds_shepp(const Pose2& from, const Pose2& to, double radius_m) {
  // OMPL solves in units of the radius, from the origin: only relative poses matter, so a unit
  // space is shared by every call (the solver itself is stateless).
  // The two OMPL states are allocated once per thread (a state needs its space to allocate it).
  struct UnitStates {
    ob::ReedsSheppStateSpace space{1.0};
    ob::SE2StateSpace::StateType* a = space.allocState()->as<ob::SE2StateSpace::StateType>();
    ob::SE2StateSpace::StateType* b = space.allocState()->as<ob::SE2StateSpace::StateType>();
    ~UnitStates() {
      space.freeState(a);
      space.freeState(b);
    }
  };
  thread_local UnitStates unit;
  const double dx = (to.x_m - from.x_m) / radius_m, dy = (to.y_m - from.y_m) / radius_m;
  unit.a->setXY(0.0, 0.0);
  unit.a->setYaw(from.yaw_rad);
  unit.b->setXY(dx, dy);
  unit.b->setYaw(to.yaw_rad);
  const auto p = unit.space.reedsShepp(unit.a, unit.b);
  RsCurve curve;
  for (int i = 0; i < 5; ++i) {
    curve.segments[i].kind = kind_of(p.type_[i]);
    curve.segments[i].length_m = p.length_[i] * radius_m;
  }
  curve.length_m = p.totalLength_ * radius_m;
  return curve;
}

double reeds_shepp_length_m(const Pose2& from, const Pose2& to, double radius_m) {
  return reeds_shepp(from, to, radius_m).length_m;
}

double reeds_shepp_upper_bound_m(const Pose2& from, const Pose2& to, double radius_m) {
  const double two_pi = 2.0 * std::numbers::pi;
  auto ccw = [two_pi](double a) {  // a turned anticlockwise into [0, 2 pi)
    a = std::fmod(a, two_pi);
    return a < 0.0 ? a + two_pi : a;
  };
  // Turn, straight, turn the same way (Dubins' LSL and RSR), driven forwards from `a` to `b`:
  // the centres of the two turning circles on the side `side` (+1 left, -1 right).
  auto csc = [&](const Pose2& a, const Pose2& b, double side) {
    const double r = radius_m * side;
    const double ax = a.x_m - r * std::sin(a.yaw_rad), ay = a.y_m + r * std::cos(a.yaw_rad);
    const double bx = b.x_m - r * std::sin(b.yaw_rad), by = b.y_m + r * std::cos(b.yaw_rad);
    const double straight = std::hypot(bx - ax, by - ay);
    const double heading = straight > 0.0 ? std::atan2(by - ay, bx - ax) : a.yaw_rad;
    return straight +
           radius_m * (ccw(side * (heading - a.yaw_rad)) + ccw(side * (b.yaw_rad - heading)));
  };
  // Backwards: the same curves with both poses turned round, driven in reverse.
  const Pose2 back_from{from.x_m, from.y_m, from.yaw_rad + std::numbers::pi};
  const Pose2 back_to{to.x_m, to.y_m, to.yaw_rad + std::numbers::pi};
  return std::min({csc(from, to, 1.0), csc(from, to, -1.0), csc(back_from, back_to, 1.0),
                   csc(back_from, back_to, -1.0)});
}

Pose2 rs_pose_at(const Pose2& from, const RsCurve& curve, double radius_m, double s_m) {
  Pose2 p = from;
  double left = s_m;
  for (const RsSegment& seg : curve.segments) {
    if (left <= 0.0 || seg.kind == RsSegment::Kind::kNone) break;
    const double v =
        seg.length_m < 0 ? std::max(-left, seg.length_m) : std::min(left, seg.length_m);
    left -= std::abs(v);
    p = advance(p, seg.kind, v, radius_m);
  }
  return p;
}

Path rs_sample(const Pose2& from, const RsCurve& curve, double radius_m, double step_m) {
  Path path{{from, false}};
  Pose2 p = from;
  for (const RsSegment& seg : curve.segments) {
    if (seg.kind == RsSegment::Kind::kNone || std::abs(seg.length_m) < 1e-9) continue;
    const int n = std::max(1, int(std::ceil(std::abs(seg.length_m) / step_m)));
    const double v = seg.length_m / n;
    if (seg.kind == RsSegment::Kind::kStraight) {
      const double dx = v * std::cos(p.yaw_rad), dy = v * std::sin(p.yaw_rad);
      for (int k = 1; k <= n; ++k)
        path.push_back({{p.x_m + k * dx, p.y_m + k * dy, p.yaw_rad}, seg.length_m < 0});
    } else {
      // Each step turns the heading by the same angle: its sine and cosine are rotated along
      // instead of recomputed (the segment's end is computed directly, so no error builds up).
      const double turn = (seg.kind == RsSegment::Kind::kLeft ? 1.0 : -1.0) * v / radius_m;
      const double side = seg.kind == RsSegment::Kind::kLeft ? radius_m : -radius_m;
      const double ct = std::cos(turn), st = std::sin(turn);
      double c = std::cos(p.yaw_rad), s = std::sin(p.yaw_rad);
      // centre of the turn: side * (-sin, cos) from the start
      const double ox = p.x_m - side * s, oy = p.y_m + side * c;
      for (int k = 1; k < n; ++k) {
        const double c2 = c * ct - s * st;
        s = s * ct + c * st;
        c = c2;
        path.push_back(
            {{ox + side * s, oy - side * c, wrap_angle(p.yaw_rad + k * turn)}, seg.length_m < 0});
      }
      path.push_back({advance(p, seg.kind, seg.length_m, radius_m), seg.length_m < 0});
    }
    p = path.back().pose;
  }
  if (path.size() > 1) path[0].reverse = path[1].reverse;
  return path;
}

}  // namespace fieldlidar::planning
