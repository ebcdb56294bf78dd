// 6-DoF motion from trunk axes (across each axis: x, y, yaw) and the ground plane (roll, pitch,
// height), by Gauss-Newton on a left perturbation of the pose.
#include <cmath>

#include <Eigen/Dense>
#include <Eigen/Geometry>

#include "fieldlidar/forest/tracking.hpp"
#include "normal_equations.hpp"

namespace fieldlidar::forest {

GroundPlane fit_ground_plane(const PointCloud& cloud, std::span<const std::uint8_t> is_ground,
                             double min_r_m, double max_r_m) {
  GroundPlane plane;
  std::vector<Eigen::Vector3d> pts;
  for (std::size_t i = 0; i < cloud.size() && i < is_ground.size(); ++i) {
    const auto& p = cloud.points[i];
    if (!is_ground[i] || !p.is_valid()) continue;
    const double r = std::hypot(p.x, p.y);
    if (r >= min_r_m && r <= max_r_m) pts.push_back(p.xyz().cast<double>());
  }
  std::vector<char> keep(pts.size(), 1);
  for (int round = 0; round < 2; ++round) {
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    std::size_t n = 0;
    for (std::size_t i = 0; i < pts.size(); ++i)
      if (keep[i]) mean += pts[i], ++n;
    if (n < 30) return GroundPlane{};
    mean /= double(n);
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (std::size_t i = 0; i < pts.size(); ++i)
      if (keep[i]) add_outer_lower<3>(cov, pts[i] - mean);
    mirror_lower(cov);
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
    Eigen::Vector3d nrm = es.eigenvectors().col(0);
    if (nrm.z() < 0) nrm = -nrm;
    plane = {nrm, -nrm.dot(mean), true};
    double ss = 0;
    for (std::size_t i = 0; i < pts.size(); ++i)
      if (keep[i]) ss += std::pow(nrm.dot(pts[i]) + plane.offset, 2);
    const double thr = 2.5 * std::sqrt(ss / double(n));
    for (std::size_t i = 0; i < pts.size(); ++i)
      keep[i] = std::abs(nrm.dot(pts[i]) + plane.offset) <= thr;
  }
  return plane;
}

namespace {

Pose exp_left(const Eigen::Matrix<double, 6, 1>& d) {
  Pose T = Pose::Identity();
  const double angle = d.head<3>().norm();
  if (angle > 1e-12) T.linear() = Eigen::AngleAxisd(angle, d.head<3>() / angle).toRotationMatrix();
  T.translation() = d.tail<3>();
  return T;
}

// Stacked, whitened residuals of pose T.
Eigen::VectorXd residuals(std::span<const TrunkLandmark> ref, std::span<const TrunkLandmark> cur,
                          std::span<const std::pair<std::size_t, std::size_t>> matches,
                          const GroundPlane& g_ref, const GroundPlane& g_cur, bool use_ground,
                          const Pose& T, const MotionConfig& c) {
  Eigen::VectorXd r(4 * matches.size() + (use_ground ? 3 : 0));
  std::size_t k = 0;
  for (const auto& [i, j] : matches) {
    const Eigen::Vector3d& a = ref[i].axis;
    const Eigen::Vector3d e1 = a.unitOrthogonal(), e2 = a.cross(e1);
    const Eigen::Vector3d v = T * cur[j].point - ref[i].point;
    r(k++) = v.dot(e1) / c.trunk_sigma_m;
    r(k++) = v.dot(e2) / c.trunk_sigma_m;
    // The axis direction: roll and pitch against the mapped stems, which do not drift.
    const Eigen::Vector3d da = T.linear() * cur[j].axis - a;
    r(k++) = da.dot(e1) / c.axis_sigma_rad;
    r(k++) = da.dot(e2) / c.axis_sigma_rad;
  }
  if (use_ground) {
    // The current plane moved into the reference frame, compared under the sensor's new place.
    const Eigen::Vector3d n = T.linear() * g_cur.normal;
    const double d = g_cur.offset - n.dot(T.translation());
    const Eigen::Vector3d dn = n - g_ref.normal;
    const Eigen::Vector3d e1 = g_ref.normal.unitOrthogonal(), e2 = g_ref.normal.cross(e1);
    r(k++) = dn.dot(e1) / c.plane_sigma_rad;
    r(k++) = dn.dot(e2) / c.plane_sigma_rad;
    // Heights of the sensor's new position above each plane agree.
    const Eigen::Vector3d s = T.translation();
    r(k++) = ((g_ref.normal.dot(s) + g_ref.offset) - (n.dot(s) + d)) / c.plane_sigma_m;
  }
  return r;
}

}  // namespace

Pose estimate_trunk_motion(std::span<const TrunkLandmark> reference,
                           std::span<const TrunkLandmark> current,
                           std::span<const std::pair<std::size_t, std::size_t>> matches,
                           const GroundPlane& reference_ground, const GroundPlane& current_ground,
                           const Pose& initial, const MotionConfig& config) {
  const bool use_ground = reference_ground.ok && current_ground.ok;
  Pose T = initial;
  for (int it = 0; it < config.iterations; ++it) {
    const Eigen::VectorXd r0 = residuals(reference, current, matches, reference_ground,
                                         current_ground, use_ground, T, config);
    Eigen::MatrixXd J(r0.size(), 6);
    for (int p = 0; p < 6; ++p) {
      Eigen::Matrix<double, 6, 1> d = Eigen::Matrix<double, 6, 1>::Zero();
      d(p) = 1e-6;
      J.col(p) = (residuals(reference, current, matches, reference_ground, current_ground,
                            use_ground, exp_left(d) * T, config) -
                  r0) /
                 1e-6;
    }
    Eigen::Matrix<double, 6, 6> H = J.transpose() * J;
    H.diagonal().array() += 1e-6;  // directions nothing constrains stay at the initial pose
    const Eigen::Matrix<double, 6, 1> step = H.ldlt().solve(-J.transpose() * r0);
    if (!step.allFinite()) break;
    T = exp_left(step) * T;
    if (step.norm() < 1e-8) break;
  }
  return T;
}

}  // namespace fieldlidar::forest
