// Angle wrapping for planar poses.

#include "fieldlidar/core/pose2.hpp"

#include <cmath>
#include <numbers>

namespace fieldlidar {

double wrap_angle(double a_rad) {
  const double a = std::remainder(a_rad, 2.0 * std::numbers::pi);  // [-pi, pi], exact
  return a == -std::numbers::pi ? std::numbers::pi : a;
}

}  // namespace fieldlidar
