#include "fieldlidar/people/scan_matcher_2d.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

#include <Eigen/Eigenvalues>

namespace fieldlidar::people {

namespace {

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

/// The target points bucketed in square cells at least as wide as the largest correspondence
/// distance: the nearest target within that distance of a query lies in the query's cell or one
/// of its 8 neighbours (exact, as a k-d tree query, and ~3x cheaper for scan-sized clouds).
class NearestGrid {
 public:
  NearestGrid(const std::vector<Eigen::Vector2d>& pts, double reach_m) {
    Eigen::Vector2d lo = pts.front(), hi = pts.front();
    for (const auto& p : pts) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    // At most ~1024 cells a side: a wider cell still holds every neighbour within reach.
    cell_m_ = std::max({reach_m, (hi - lo).maxCoeff() / 1024.0, 1e-6});
    origin_ = lo;
    nx_ = int((hi.x() - lo.x()) / cell_m_) + 1;
    ny_ = int((hi.y() - lo.y()) / cell_m_) + 1;
    start_.assign(std::size_t(nx_) * std::size_t(ny_) + 1, 0);
    std::vector<std::uint32_t> cell(pts.size());
    for (std::size_t i = 0; i < pts.size(); ++i) {
      cell[i] = std::uint32_t(index(cx(pts[i]), cy(pts[i])));
      ++start_[cell[i] + 1];
    }
    for (std::size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
    order_.resize(pts.size());
    std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
    for (std::size_t i = 0; i < pts.size(); ++i) order_[fill[cell[i]]++] = std::uint32_t(i);
    sorted_.reserve(pts.size());
    for (const auto i : order_) sorted_.push_back(pts[i]);
  }
  /// The target point nearest to `q` if one lies within sqrt(max_d2) <= reach_m: its index and
  /// squared distance (the squared distance is above max_d2 when none does). The query's own
  /// cell is searched first; a neighbour cell only when it may hold a nearer point.
  std::pair<std::uint32_t, double> nearest(const Eigen::Vector2d& q, double max_d2) const {
    std::uint32_t best = 0;
    double best_d2 = std::nextafter(max_d2, std::numeric_limits<double>::infinity());
    const double fx = std::floor((q.x() - origin_.x()) / cell_m_);
    const double fy = std::floor((q.y() - origin_.y()) / cell_m_);
    if (fx < -1 || fy < -1 || fx > nx_ || fy > ny_) return {best, best_d2};
    const int x = int(fx), y = int(fy);
    const auto search = [&](int i, int j) {
      if (i < 0 || j < 0 || i >= nx_ || j >= ny_) return;
      const auto c = index(i, j);
      for (auto k = start_[c]; k < start_[c + 1]; ++k) {
        const auto& p = sorted_[k];
        const double dx = q.x() - p.x(), dy = q.y() - p.y();
        const double d2 = dx * dx + dy * dy;
        if (d2 < best_d2) {
          best_d2 = d2;
          best = order_[k];
        }
      }
    };
    search(x, y);
    // Distances from q to its cell's borders (low side, high side) in x and y.
    const double x0 = q.x() - (origin_.x() + x * cell_m_), x1 = cell_m_ - x0;
    const double y0 = q.y() - (origin_.y() + y * cell_m_), y1 = cell_m_ - y0;
    for (int dj = -1; dj <= 1; ++dj)
      for (int di = -1; di <= 1; ++di) {
        if (di == 0 && dj == 0) continue;
        const double gx = di < 0 ? x0 : di > 0 ? x1 : 0.0;
        const double gy = dj < 0 ? y0 : dj > 0 ? y1 : 0.0;
        if (gx * gx + gy * gy < best_d2) search(x + di, y + dj);
      }
    return {best, best_d2};
  }
  /// The target points closer than sqrt(r2) <= reach_m to a point `q` of the target cloud (not
  /// beyond its bounds), as (index, squared distance), nearest first (a k-d tree's order).
  void within(const Eigen::Vector2d& q, double r2,
              std::vector<std::pair<std::uint32_t, double>>& out) const {
    out.clear();
    const int x = cx(q), y = cy(q);
    for (int j = std::max(y - 1, 0); j <= std::min(y + 1, ny_ - 1); ++j)
      for (int i = std::max(x - 1, 0); i <= std::min(x + 1, nx_ - 1); ++i) {
        const auto c = index(i, j);
        for (auto k = start_[c]; k < start_[c + 1]; ++k) {
          const auto& p = sorted_[k];
          const double dx = q.x() - p.x(), dy = q.y() - p.y();
          const double d2 = dx * dx + dy * dy;
          if (d2 < r2) out.emplace_back(order_[k], d2);
        }
      }
    std::sort(out.begin(), out.end(),
              [](const auto& u, const auto& v) { return u.second < v.second; });
  }

 private:
  int cx(const Eigen::Vector2d& p) const {
    return std::min(int((p.x() - origin_.x()) / cell_m_), nx_ - 1);
  }
  int cy(const Eigen::Vector2d& p) const {
    return std::min(int((p.y() - origin_.y()) / cell_m_), ny_ - 1);
  }
  std::size_t index(int i, int j) const {
    return std::size_t(j) * std::size_t(nx_) + std::size_t(i);
  }
  std::vector<Eigen::Vector2d> sorted_;  ///< the points in cell order
  Eigen::Vector2d origin_;
  double cell_m_ = 1;
  int nx_ = 1, ny_ = 1;
  std::vector<std::uint32_t> start_, order_;
};

/// Unit normals of the target points from their neighbours within `radius_m` (the smallest
/// principal axis); zero where the neighbourhood is not a line (corners, lone points).
std::vector<Eigen::Vector2d> normals_of(const std::vector<Eigen::Vector2d>& pts,
                                        const NearestGrid& grid, double radius_m) {
  std::vector<Eigen::Vector2d> normals(pts.size(), Eigen::Vector2d::Zero());
  std::vector<std::pair<std::uint32_t, double>> found;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    grid.within(pts[i], radius_m * radius_m, found);
    if (found.size() < 3) continue;
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (const auto& f : found) mean += pts[f.first];
    mean /= double(found.size());
    Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
    for (const auto& f : found) {
      const Eigen::Vector2d d = pts[f.first] - mean;
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
  const auto target = thin(previous, c.subsample_m, c.max_range_m);
  const auto source = thin(current, c.subsample_m, c.max_range_m);
  if (target.size() < 10 || source.size() < 10) return m;
  double limit = std::max(c.max_correspondence_m, c.min_correspondence_m);
  const double normal_radius_m = 3.0 * c.subsample_m;
  // A coarse grid while the correspondence limit is wide, a fine one once it has shrunk (and
  // for the normals).
  const double fine_reach_m = std::max(2.0 * c.min_correspondence_m, normal_radius_m);
  const NearestGrid fine(target, fine_reach_m);
  const NearestGrid coarse(target, std::max(limit, fine_reach_m));
  const auto grid_for = [&](double reach_m) -> const NearestGrid& {
    return reach_m <= fine_reach_m ? fine : coarse;
  };
  const auto normals = normals_of(target, fine, normal_radius_m);
  std::vector<Eigen::Vector2d> a, b, n;
  a.reserve(source.size());
  b.reserve(source.size());
  n.reserve(source.size());
  for (int it = 0; it < c.max_iterations; ++it) {
    a.clear();
    b.clear();
    n.clear();
    const NearestGrid& grid = grid_for(limit);
    for (const auto& p : source) {
      const Eigen::Vector2d q = m.transform * p;
      const auto [idx, d2] = grid.nearest(q, limit * limit);
      if (d2 <= limit * limit) {
        a.push_back(q);
        b.push_back(target[idx]);
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
    const double d2 = fine.nearest(m.transform * p, tight2).second;
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

bool ScanOdometry2D::implausible(const Eigen::Isometry2d& step, double dt_s) const {
  const Eigen::Vector2d v = step.translation() / dt_s;
  const double turn_rate = std::abs(Eigen::Rotation2Dd(step.linear()).angle()) / dt_s;
  if (config_.max_speed_m_s > 0 && v.norm() > config_.max_speed_m_s) return true;
  if (config_.max_turn_rate_rad_s > 0 && turn_rate > config_.max_turn_rate_rad_s) return true;
  // The velocity changes by at most max_accel over the time since the last step believed (so
  // a run of refusals ends once that much time allows the change).
  return config_.max_accel_m_s2 > 0 && believed_velocity_ &&
         (v - *believed_velocity_).norm() > config_.max_accel_m_s2 * (dt_s + refused_s_);
}

const Eigen::Isometry2d& ScanOdometry2D::add(std::span<const Eigen::Vector2d> scan, double dt_s) {
  if (started_) {
    last_ = match_scans_2d(previous_, scan, last_step_, config_);
    if (last_.ok && dt_s > 0 && implausible(last_.transform, dt_s)) {
      last_.ok = false;
      last_.too_fast = true;
      last_.transform = last_step_;
    }
    if (dt_s > 0) {
      if (last_.ok) {
        believed_velocity_ = Eigen::Vector2d(last_.transform.translation() / dt_s);
        refused_s_ = 0;
      } else {
        refused_s_ += dt_s;
      }
    }
    if (!last_.ok) ++failed_;
    last_step_ = last_.transform;
    pose_ = pose_ * last_step_;
  }
  started_ = true;
  previous_.assign(scan.begin(), scan.end());
  return pose_;
}

}  // namespace fieldlidar::people
