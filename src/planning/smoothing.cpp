// Seed 004, f42: conjugate-gradient path smoothing (Dolgov, Thrun, Montemerlo, Diebel 2010):
// minimise w_o sum (d_max - d_i)^2 [d_i < d_max] + w_s sum |x_{i+1} - 2 x_i + x_{i-1}|^2
//        + w_k sum (kappa_i - kappa_max)^2 [kappa_i > kappa_max]
// over the free samples of each forward or reverse run (ends and cusps fixed), then keep the
// largest share of the change that leaves every footprint free and kappa <= kappa_max.

#include "fieldlidar/planning/smoothing.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "fieldlidar/planning/planning_map.hpp"

namespace fieldlidar::planning {
namespace {

using Points = std::vector<Eigen::Vector2d>;

double menger(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  const Eigen::Vector2d ab = b - a, bc = c - b, ac = c - a;
  const double l = ab.norm() * bc.norm() * ac.norm();
  if (l < 1e-12) return 0.0;
  return 2.0 * std::abs(ab.x() * ac.y() - ab.y() * ac.x()) / l;
}

class Objective {
 public:
  Objective(const PlanningMap& map, double kappa_max, const SmoothingConfig& c)
      : map_(map), kappa_max_(kappa_max * c.curvature_target_share), c_(c) {}

  // The obstacle term at a point, and its gradient when `grad` is given (the distance field is
  // bilinear between cell centres, as PlanningMap::obstacle_distance_at).
  double obstacle(const Eigen::Vector2d& p, Eigen::Vector2d* grad) const {
    const GridGeometry& g = map_.geometry();
    const double fx = (p.x() - g.origin_m.x()) / g.resolution_m - 0.5;
    const double fy = (p.y() - g.origin_m.y()) / g.resolution_m - 0.5;
    const int x0 = std::clamp(int(std::floor(fx)), 0, g.width - 1);
    const int y0 = std::clamp(int(std::floor(fy)), 0, g.height - 1);
    const int x1 = std::min(x0 + 1, g.width - 1), y1 = std::min(y0 + 1, g.height - 1);
    const double tx = std::clamp(fx - x0, 0.0, 1.0), ty = std::clamp(fy - y0, 0.0, 1.0);
    auto at = [&](int x, int y) {
      return double(map_.obstacle_distance_m(std::size_t(y) * g.width + x));
    };
    const double d00 = at(x0, y0), d10 = at(x1, y0), d01 = at(x0, y1), d11 = at(x1, y1);
    const double d = (1 - ty) * ((1 - tx) * d00 + tx * d10) + ty * ((1 - tx) * d01 + tx * d11);
    const double gap = c_.obstacle_distance_m - d;
    if (gap <= 0.0) {
      if (grad) grad->setZero();
      return 0.0;
    }
    if (grad) {
      // d/dx of the bilinear form (0 where the point is clamped at the map's edge)
      const double ddx = ((1 - ty) * (d10 - d00) + ty * (d11 - d01)) / g.resolution_m;
      const double ddy = ((1 - tx) * (d01 - d00) + tx * (d11 - d10)) / g.resolution_m;
      *grad = -2.0 * c_.weight_obstacle * gap * Eigen::Vector2d(ddx, ddy);
    }
    return c_.weight_obstacle * gap * gap;
  }
  double curvature(const Points& x, std::size_t i) const {
    const double k = menger(x[i - 1], x[i], x[i + 1]);
    return k > kappa_max_ ? c_.weight_curvature * (k - kappa_max_) * (k - kappa_max_) : 0.0;
  }
  // Terms centred on sample i (1 <= i <= n-2).
  double term(const Points& x, std::size_t i) const {
    return obstacle(x[i], nullptr) +
           c_.weight_smoothness * (x[i + 1] - 2.0 * x[i] + x[i - 1]).squaredNorm() +
           curvature(x, i);
  }
  double value(const Points& x) const {
    double f = 0.0;
    for (std::size_t i = 1; i + 1 < x.size(); ++i) f += term(x, i);
    return f;
  }
  // Gradient: the obstacle and smoothness terms in closed form, the curvature terms by central
  // differences where they are active.
  void gradient(Points& x, Points& g) const {
    const std::size_t n = x.size();
    g.assign(n, Eigen::Vector2d::Zero());
    Eigen::Vector2d go;
    for (std::size_t i = 1; i + 1 < n; ++i) {
      obstacle(x[i], &go);
      g[i] += go;
      const Eigen::Vector2d lap = 2.0 * c_.weight_smoothness * (x[i + 1] - 2.0 * x[i] + x[i - 1]);
      g[i - 1] += lap;
      g[i] -= 2.0 * lap;
      g[i + 1] += lap;
      if (curvature(x, i) > 0.0) {
        const double h = 1e-5;
        for (std::size_t j = i - 1; j <= i + 1; ++j)
          for (int a = 0; a < 2; ++a) {
            const double keep = x[j][a];
            x[j][a] = keep + h;
            const double fp = curvature(x, i);
            x[j][a] = keep - h;
            const double fm = curvature(x, i);
            x[j][a] = keep;
            g[j][a] += (fp - fm) / (2.0 * h);
          }
      }
    }
    // two vertices fixed at each end: the end poses and the headings into them stay
    for (std::size_t i = 0; i < n; ++i)
      if (i < 2 || i + 2 >= n) g[i].setZero();
  }

 private:
  const PlanningMap& map_;
  double kappa_max_;
  const SmoothingConfig& c_;
};

double dot(const Points& a, const Points& b) {
  double s = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) s += a[i].dot(b[i]);
  return s;
}

// Polak–Ribière conjugate gradient with a backtracking (Armijo) line search.
int conjugate_gradient(Points& x, const Objective& f, int max_iterations) {
  Points g, g_old, d, trial;
  f.gradient(x, g);
  d.resize(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) d[i] = -g[i];
  double fx = f.value(x);
  double last_step = 0.0;
  const double f_start = fx;
  int it = 0;
  for (; it < max_iterations; ++it) {
    double slope = dot(g, d);
    if (slope >= 0.0) {  // not a descent direction: restart along the gradient
      for (std::size_t i = 0; i < x.size(); ++i) d[i] = -g[i];
      slope = dot(g, d);
    }
    if (-slope < 1e-12) break;
    // first try: twice the last accepted step, or 5 cm of mean displacement
    double step = last_step > 0.0 ? 2.0 * last_step
                                  : 0.05 / std::max(1e-9, std::sqrt(dot(d, d) / double(x.size())));
    bool moved = false;
    for (int ls = 0; ls < 20; ++ls, step *= 0.5) {
      trial = x;
      for (std::size_t i = 0; i < x.size(); ++i) trial[i] += step * d[i];
      const double ft = f.value(trial);
      if (ft <= fx + 1e-4 * step * slope) {
        x.swap(trial);
        fx = ft;
        last_step = step;
        moved = true;
        break;
      }
    }
    if (!moved) break;
    if (it > 5 && (f_start - fx) < 1e-4 * std::max(1e-9, f_start)) break;
    g_old.swap(g);
    f.gradient(x, g);
    double beta = 0.0;
    const double denom = dot(g_old, g_old);
    if (denom > 0.0) {
      double num = 0.0;
      for (std::size_t i = 0; i < x.size(); ++i) num += g[i].dot(g[i] - g_old[i]);
      beta = std::max(0.0, num / denom);
    }
    for (std::size_t i = 0; i < x.size(); ++i) d[i] = -g[i] + beta * d[i];
  }
  return it;
}

// Headings of run [a, b] from the positions (the tangent; flipped on a reverse run), the run's
// end samples keeping theirs.
void set_headings(Path& p, std::size_t a, std::size_t b) {
  const bool reverse = p[b].reverse;
  for (std::size_t i = a + 1; i < b; ++i) {
    const double dx = p[i + 1].pose.x_m - p[i - 1].pose.x_m;
    const double dy = p[i + 1].pose.y_m - p[i - 1].pose.y_m;
    double yaw = std::atan2(dy, dx);
    if (reverse) yaw += M_PI;
    p[i].pose.yaw_rad = wrap_angle(yaw);
  }
}

// Sum over the path's steps of length * (1 + w (1 - tau)) at the step's end cell.
double tau_cost(const Path& p, const PlanningMap& map, double w) {
  double c = 0.0;
  for (std::size_t i = 1; i < p.size(); ++i) {
    const long cell = map.cell_index(p[i].pose.x_m, p[i].pose.y_m);
    const double tau = cell < 0 ? 0.0 : map.tau(std::size_t(cell));
    c += std::hypot(p[i].pose.x_m - p[i - 1].pose.x_m, p[i].pose.y_m - p[i - 1].pose.y_m) *
         (1.0 + w * (1.0 - tau));
  }
  return c;
}

// Catmull–Rom interpolation of points d (clamped at the ends) at vertex j + t.
Eigen::Vector2d displacement_at(const Points& d, std::size_t j, double t) {
  const std::size_t n = d.size();
  const Eigen::Vector2d& p0 = d[j == 0 ? 0 : j - 1];
  const Eigen::Vector2d& p1 = d[j];
  const Eigen::Vector2d& p2 = d[std::min(n - 1, j + 1)];
  const Eigen::Vector2d& p3 = d[std::min(n - 1, j + 2)];
  const double t2 = t * t, t3 = t2 * t;
  return 0.5 * ((2.0 * p1) + (-p0 + p2) * t + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * t2 +
                (-p0 + 3.0 * p1 - 3.0 * p2 + p3) * t3);
}

}  // namespace

Path smooth_path(const Path& path, const PlanningMap& map, double kappa_max,
                 const SmoothingConfig& config, SmoothingReport* report) {
  Path out = path;
  SmoothingReport r;
  r.length_before_m = path_length_m(path);
  r.turning_before_rad = total_turning_rad(path);
  const Objective f(map, kappa_max, config);
  double kept_weight = 0.0, kept_total = 0.0;
  std::size_t a = 0;
  while (a + 1 < path.size()) {
    std::size_t b = a + 1;  // run [a, b]: samples a+1..b share a direction
    while (b + 1 < path.size() && path[b + 1].reverse == path[a + 1].reverse) ++b;
    // the run's vertices: about vertex_spacing_m apart, its ends included
    const double spacing =
        path_length_m(Path(path.begin() + long(a), path.begin() + long(b) + 1)) / double(b - a);
    const std::size_t k = std::max<std::size_t>(
        1, std::size_t(std::lround(config.vertex_spacing_m / std::max(1e-6, spacing))));
    std::vector<std::size_t> vi;
    for (std::size_t i = a; i < b; i += k) vi.push_back(i);
    if (vi.size() > 1 && 2 * (b - vi.back()) < k) vi.pop_back();  // no short last interval
    vi.push_back(b);
    if (vi.size() >= 8) {
      Points x0(vi.size()), x;
      for (std::size_t j = 0; j < vi.size(); ++j)
        x0[j] = {path[vi[j]].pose.x_m, path[vi[j]].pose.y_m};
      x = x0;
      r.iterations += conjugate_gradient(x, f, config.max_iterations);
      const Path base(path.begin() + long(a), path.begin() + long(b) + 1);
      const double base_length = path_length_m(base), base_turning = total_turning_rad(base);
      const double base_cost = tau_cost(base, map, config.tau_weight);
      // The smoothed curve: a Catmull–Rom spline through the optimised vertices, sampled where
      // the path's samples were. Kept in the largest share alpha of the change (base + alpha *
      // (spline - base)) for which every sample's footprint is free, kappa <= kappa_max, and the
      // run is no longer and turns no more than before.
      Path spline = base;
      std::size_t j = 0;
      for (std::size_t i = a + 1; i < b; ++i) {
        while (j + 1 < vi.size() && vi[j + 1] <= i) ++j;
        const double t = j + 1 < vi.size() ? double(i - vi[j]) / double(vi[j + 1] - vi[j]) : 0.0;
        const Eigen::Vector2d p = displacement_at(x, j, t);
        spline[i - a].pose.x_m = p.x();
        spline[i - a].pose.y_m = p.y();
      }
      // The change fades in and out over the first and last three vertex intervals (a smooth
      // step), so the run leaves and reaches its fixed ends with their headings and no kink.
      std::vector<double> ramp(base.size(), 1.0);
      const double fade = 3.0 * double(k);
      for (std::size_t i = 0; i < base.size(); ++i) {
        const double u =
            std::clamp(std::min(double(i), double(base.size() - 1 - i)) / fade, 0.0, 1.0);
        ramp[i] = u * u * u * (u * (6.0 * u - 15.0) + 10.0);  // smootherstep: C2 at both ends
      }
      // Where a sample still bends above kappa_max or touches a blocked cell (the search's
      // arcs already run at kappa_max), the change dips smoothly to nothing around it (a
      // smootherstep over three vertex intervals); the dips and a global share alpha are
      // tightened until every sample is fine and the run is no longer, turns no more and costs
      // no more than before.
      auto smootherstep = [](double u) { return u * u * u * (u * (6.0 * u - 15.0) + 10.0); };
      double alpha = 1.0;
      bool accepted = false;
      for (; alpha > 1.0 / 64 && !accepted; alpha *= 0.5) {
        std::vector<double> local(base.size(), 1.0);
        for (int round = 0; round < 8; ++round) {
          Path trial = base;
          for (std::size_t i = 1; i + 1 < trial.size(); ++i) {
            const double w = alpha * ramp[i] * local[i];
            trial[i].pose.x_m += w * (spline[i].pose.x_m - base[i].pose.x_m);
            trial[i].pose.y_m += w * (spline[i].pose.y_m - base[i].pose.y_m);
          }
          set_headings(trial, 0, trial.size() - 1);
          std::vector<std::size_t> bad;
          for (std::size_t i = 1; i + 1 < trial.size(); ++i)
            if (menger_curvature(trial, i) > kappa_max * (1.0 + 1e-6) ||
                !map.pose_free(trial[i].pose))
              bad.push_back(i);
          if (bad.empty()) {
            if (path_length_m(trial) <= base_length + 1e-9 &&
                total_turning_rad(trial) <= base_turning + 1e-9 &&
                tau_cost(trial, map, config.tau_weight) <= base_cost + 1e-9) {
              std::copy(trial.begin(), trial.end(), out.begin() + long(a));
              accepted = true;
            }
            break;
          }
          const double kk = double(k);
          for (std::size_t v : bad) {
            const std::size_t lo = v > 4 * k ? v - 4 * k : 0;
            const std::size_t hi = std::min(base.size() - 1, v + 4 * k);
            for (std::size_t i = lo; i <= hi; ++i) {
              const double dist = std::abs(double(i) - double(v));
              local[i] =
                  std::min(local[i], smootherstep(std::clamp((dist - kk) / (3.0 * kk), 0.0, 1.0)));
            }
          }
        }
      }
      if (accepted)
        alpha *= 2.0;  // undo the loop's last halving
      else
        alpha = 0.0;
      if (alpha <= 1.0 / 64) alpha = 0.0;
      kept_weight += alpha * double(b - a);
      kept_total += double(b - a);
    }
    a = b;
  }
  r.blend = kept_total > 0 ? kept_weight / kept_total : 0.0;
  r.length_after_m = path_length_m(out);
  r.turning_after_rad = total_turning_rad(out);
  r.max_curvature_after = max_curvature(out);
  if (report) *report = r;
  return out;
}

}  // namespace fieldlidar::planning
