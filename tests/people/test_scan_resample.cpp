// A coarser laser's scan resampled to the classifier's angular step (people::resample_scan,
// people::scan_step_rad), on synthetic scans.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "fieldlidar/people/scan_resample.hpp"

namespace fieldlidar::people {
namespace {

constexpr double kDeg = M_PI / 180.0;

/// A wall 3 m ahead (x = 3) over bearings -20..-5 deg and a leg (circle of radius 0.06 m at 2 m,
/// bearing 10 deg) seen every `step_deg`, in beam order.
std::vector<Eigen::Vector2d> scene(double step_deg) {
  std::vector<Eigen::Vector2d> pts;
  const Eigen::Vector2d c = 2.0 * Eigen::Vector2d(std::cos(10 * kDeg), std::sin(10 * kDeg));
  for (double a = -20; a <= 20 + 1e-9; a += step_deg) {
    const Eigen::Vector2d u(std::cos(a * kDeg), std::sin(a * kDeg));
    if (a <= -5) {
      pts.push_back(u * (3.0 / u.x()));
      continue;
    }
    const double b = u.dot(c), disc = b * b - (c.squaredNorm() - 0.06 * 0.06);
    if (disc >= 0) pts.push_back(u * (b - std::sqrt(disc)));
  }
  return pts;
}

TEST(ScanResample, StepOfAScan) {
  EXPECT_NEAR(scan_step_rad(scene(0.7)), 0.7 * kDeg, 1e-9);
  EXPECT_NEAR(scan_step_rad(scene(0.35)), 0.35 * kDeg, 1e-9);
  EXPECT_EQ(scan_step_rad(std::vector<Eigen::Vector2d>(5, Eigen::Vector2d(1, 0))), 0.0);
}

TEST(ScanResample, CoarseScanResampledOnItsSurfacesOnly) {
  const auto coarse = scene(0.7);
  const auto fine = resample_scan(coarse, 0.35 * kDeg, 0.13);
  EXPECT_NEAR(scan_step_rad(fine), 0.35 * kDeg, 0.01 * kDeg);
  std::size_t wall = 0, leg = 0, other = 0;
  const Eigen::Vector2d c = 2.0 * Eigen::Vector2d(std::cos(10 * kDeg), std::sin(10 * kDeg));
  for (const auto& p : fine) {
    if (std::abs(p.x() - 3.0) < 0.002) {
      ++wall;  // the wall's samples stay on the wall within 2 mm
    } else if (std::abs((p - c).norm() - 0.06) < 0.005) {
      ++leg;  // the leg's stay on its circle within 5 mm
    } else {
      ++other;
    }
  }
  EXPECT_EQ(other, 0u);  // nothing between the wall and the leg: a jump is not bridged
  std::size_t coarse_leg = 0;
  for (const auto& p : coarse) coarse_leg += std::abs((p - c).norm() - 0.06) < 1e-9;
  EXPECT_EQ(wall, 2 * 22 - 1);         // 22 wall returns at 0.7 deg: 43 at 0.35
  EXPECT_EQ(leg, 2 * coarse_leg - 1);  // twice the leg's returns, less one
  // Already at the step: unchanged.
  const auto same = resample_scan(scene(0.35), 0.35 * kDeg, 0.13);
  EXPECT_EQ(same.size(), scene(0.35).size());
}

TEST(ScanResample, APointAloneAndBearingsFallingAreKept) {
  std::vector<Eigen::Vector2d> pts = {{2, 0}, {4, 0.2}, {2, 0.05}};  // no two on one surface
  EXPECT_EQ(resample_scan(pts, 0.35 * kDeg, 0.13).size(), 3u);
  auto reversed = scene(0.7);
  std::reverse(reversed.begin(), reversed.end());  // clockwise: left as it is
  EXPECT_EQ(resample_scan(reversed, 0.35 * kDeg, 0.13).size(), reversed.size());
}

}  // namespace
}  // namespace fieldlidar::people
