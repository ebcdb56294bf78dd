#include "fieldlidar/people/scan_matcher_2d.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

#include <Eigen/Eigenvalues>
#include <nanoflann.hpp>

namespace fieldlidar::people {

namespace {

struct Cloud2 {
  std::vector<Eigen::Vector2d> pts;
  std::size_t kdtree_get_point_count() const { return pts.size(); }
  double kdtree_get_pt(std::size_t i, std::size_t dim) const { return pts[i][Eigen::Index(dim)]; }
  template <class Bbox>
  bool kdtree_get_bbox(Bbox&) const {
    return false;
  }
};

using KdTree2 = nanoflann::KDTreeSingleIndexAdaptor<
    nanoflann::L2_Simple_Adaptor<double, Cloud2, double, std::uint32_t>, Cloud2, 2, std::uint32_t>;

/// Finite points within range, thinned to one per `spacing_m` along the scan order.
std::vector<Eigen::Vector2d> thin(std::span<const Eigen::Vector2d> scan, double spacing_m,
                                  double max_range_m) {
  std::vector<Eigen::Vector2d> out;
  out.reserve(scan.size());
  for (const auto& p : scan) {
    if (!p.allFinite() || p.norm() > max_range_m || p.norm() < 1e-3) continue;
    if (!out.empty() && (p - out.back()).norm() < spacing_m) continue;
    out.push_back(p);
  }
  return out;
}

/// The target point nearest to `q`: its index and squared distance.
std::pair<std::uint32_t, double> nearest(const KdTree2& tree, const Eigen::Vector2d& q) {
  std::uint32_t idx = 0;
  double d2 = 0;
  nanoflann::KNNResultSet<double, std::uint32_t> result(1);
  result.init(&idx, &d2);
  tree.findNeighbors(result, q.data(), nanoflann::SearchParams(10));
  return {idx, d2};
}

/// Unit normals of the target points from their neighbours within `radius_m` (the smallest
/// principal axis); zero where the neighbourhood is not a line (corners, lone points).
std::vector<Eigen::Vector2d> normals_of(const Cloud2& cloud, const KdTree2& tree, double radius_m) {
  std::vector<Eigen::Vector2d> normals(cloud.pts.size(), Eigen::Vector2d::Zero());
  std::vector<std::pair<std::uint32_t, double>> found;
  for (std::size_t i = 0; i < cloud.pts.size(); ++i) {
    found.clear();
    tree.radiusSearch(cloud.pts[i].data(), radius_m * radius_m, found, nanoflann::SearchParams());
    if (found.size() < 3) continue;
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (const auto& f : found) mean += cloud.pts[f.first];
    mean /= double(found.size());
    Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
    for (const auto& f : found) {
      const Eigen::Vector2d d = cloud.pts[f.first] - mean;
      cov += d * d.transpose();
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(cov);
    if (es.eigenvalues()[0] > 0.05 * es.eigenvalues()[1]) continue;  // not a line
    normals[i] = es.eigenvectors().col(0);
  }
  return normals;
}

/// One Gauss-Newton step of point-to-line (point-to-point where a target has no normal) error
/// for a small motion [dx, dy, dtheta] applied to the source points `a` matched to targets.
Eigen::Isometry2d solve_step(const std::vector<Eigen::Vector2d>& a,
                             const std::vector<Eigen::Vector2d>& b,
                             const std::vector<Eigen::Vector2d>& n) {
  Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
  Eigen::Vector3d g = Eigen::Vector3d::Zero();
  auto add_row = [&](const Eigen::Vector3d& j, double r) {
    h += j * j.transpose();
    g += j * r;
  };
  for (std::size_t i = 0; i < a.size(); ++i) {
    const Eigen::Vector2d& p = a[i];
    const Eigen::Vector2d e = p - b[i];
    const Eigen::Vector2d dp(-p.y(), p.x());  // d(R p)/d theta at theta = 0
    if (n[i].squaredNorm() > 0) {
      add_row(Eigen::Vector3d(n[i].x(), n[i].y(), n[i].dot(dp)), n[i].dot(e));
    } else {
      add_row(Eigen::Vector3d(1, 0, dp.x()), e.x());
      add_row(Eigen::Vector3d(0, 1, dp.y()), e.y());
    }
  }
  h += 1e-9 * Eigen::Matrix3d::Identity();
  const Eigen::Vector3d x = -h.ldlt().solve(g);
  Eigen::Isometry2d t = Eigen::Isometry2d::Identity();
  t.linear() = Eigen::Rotation2Dd(x[2]).toRotationMatrix();
  t.translation() = x.head<2>();
  return t;
}

}  // namespace

ScanMatch match_scans_2d(std::span<const Eigen::Vector2d> previous,
                         std::span<const Eigen::Vector2d> current,
                         const Eigen::Isometry2d& initial_guess, const ScanMatcher2DConfig& c) {
  ScanMatch m;
  m.transform = initial_guess;
  Cloud2 target{thin(previous, c.subsample_m, c.max_range_m)};
  const auto source = thin(current, c.subsample_m, c.max_range_m);
  if (target.pts.size() < 10 || source.size() < 10) return m;
  KdTree2 tree(2, target, nanoflann::KDTreeSingleIndexAdaptorParams(10));
  tree.buildIndex();
  const auto normals = normals_of(target, tree, 3.0 * c.subsample_m);
  std::vector<Eigen::Vector2d> a, b, n;
  a.reserve(source.size());
  b.reserve(source.size());
  n.reserve(source.size());
  double limit = std::max(c.max_correspondence_m, c.min_correspondence_m);
  for (int it = 0; it < c.max_iterations; ++it) {
    a.clear();
    b.clear();
    n.clear();
    for (const auto& p : source) {
      const Eigen::Vector2d q = m.transform * p;
      const auto [idx, d2] = nearest(tree, q);
      if (d2 <= limit * limit) {
        a.push_back(q);
        b.push_back(target.pts[idx]);
        n.push_back(normals[idx]);
      }
    }
    m.iterations = it + 1;
    if (a.size() < 10) break;
    const Eigen::Isometry2d step = solve_step(a, b, n);
    m.transform = step * m.transform;
    const double dt = step.translation().norm();
    const double dr = std::abs(Eigen::Rotation2Dd(step.linear()).angle());
    // Shrink the correspondence distance as the alignment settles (outliers drop out).
    limit = std::max(c.min_correspondence_m, std::min(limit, c.min_correspondence_m + 4.0 * dt));
    if (dt < c.converged_translation_m && dr < c.converged_rotation_rad &&
        limit <= c.min_correspondence_m + 4.0 * c.converged_translation_m)
      break;
  }
  // Final quality: correspondences within the tightest limit.
  std::size_t inliers = 0;
  double sum2 = 0;
  const double tight2 = c.min_correspondence_m * c.min_correspondence_m;
  for (const auto& p : source) {
    const double d2 = nearest(tree, m.transform * p).second;
    if (d2 <= tight2) {
      ++inliers;
      sum2 += d2;
    }
  }
  m.inlier_fraction = double(inliers) / double(source.size());
  m.rms_m = inliers ? std::sqrt(sum2 / double(inliers)) : 0.0;
  m.ok = m.inlier_fraction >= c.min_inlier_fraction;
  if (!m.ok) m.transform = initial_guess;
  return m;
}

ScanOdometry2D::ScanOdometry2D(const ScanMatcher2DConfig& config) : config_(config) {}

const Eigen::Isometry2d& ScanOdometry2D::add(std::span<const Eigen::Vector2d> scan) {
  if (started_) {
    last_ = match_scans_2d(previous_, scan, last_step_, config_);
    if (!last_.ok) ++failed_;
    last_step_ = last_.transform;
    pose_ = pose_ * last_step_;
  }
  started_ = true;
  previous_.assign(scan.begin(), scan.end());
  return pose_;
}

}  // namespace fieldlidar::people
