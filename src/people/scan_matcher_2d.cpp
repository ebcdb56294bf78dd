#include "fieldlidar/people/scan_matcher_2d.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

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

/// Closed-form 2D rigid alignment (Umeyama without scale) of pairs b_i ~ R a_i + t.
Eigen::Isometry2d align(const std::vector<Eigen::Vector2d>& a,
                        const std::vector<Eigen::Vector2d>& b) {
  Eigen::Vector2d ca = Eigen::Vector2d::Zero(), cb = Eigen::Vector2d::Zero();
  for (std::size_t i = 0; i < a.size(); ++i) {
    ca += a[i];
    cb += b[i];
  }
  ca /= double(a.size());
  cb /= double(b.size());
  double sxx = 0, sxy = 0;  // sum of dot and cross products of the centred pairs
  for (std::size_t i = 0; i < a.size(); ++i) {
    const Eigen::Vector2d p = a[i] - ca, q = b[i] - cb;
    sxx += p.dot(q);
    sxy += p.x() * q.y() - p.y() * q.x();
  }
  const double theta = std::atan2(sxy, sxx);
  Eigen::Isometry2d t = Eigen::Isometry2d::Identity();
  t.linear() = Eigen::Rotation2Dd(theta).toRotationMatrix();
  t.translation() = cb - t.linear() * ca;
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
  std::vector<Eigen::Vector2d> a, b;
  a.reserve(source.size());
  b.reserve(source.size());
  double limit = std::max(c.max_correspondence_m, c.min_correspondence_m);
  for (int it = 0; it < c.max_iterations; ++it) {
    a.clear();
    b.clear();
    for (const auto& p : source) {
      const Eigen::Vector2d q = m.transform * p;
      std::uint32_t idx = 0;
      double d2 = 0;
      nanoflann::KNNResultSet<double, std::uint32_t> result(1);
      result.init(&idx, &d2);
      tree.findNeighbors(result, q.data(), nanoflann::SearchParams(10));
      if (d2 <= limit * limit) {
        a.push_back(q);
        b.push_back(target.pts[idx]);
      }
    }
    m.iterations = it + 1;
    if (a.size() < 10) break;
    const Eigen::Isometry2d step = align(a, b);
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
    const Eigen::Vector2d q = m.transform * p;
    std::uint32_t idx = 0;
    double d2 = 0;
    nanoflann::KNNResultSet<double, std::uint32_t> result(1);
    result.init(&idx, &d2);
    tree.findNeighbors(result, q.data(), nanoflann::SearchParams(10));
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
