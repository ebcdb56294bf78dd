#include "fieldlidar/people/assignment.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fieldlidar::people {

std::vector<int> solve_assignment(const Eigen::MatrixXd& cost_in, double forbidden) {
  const int rows = int(cost_in.rows()), cols = int(cost_in.cols());
  std::vector<int> result(std::size_t(rows), -1);
  if (rows == 0 || cols == 0) return result;
  // Square matrix of size n; forbidden and padding entries get a large finite cost so that the
  // O(n^3) potentials method always finds a perfect matching, then those pairs are dropped.
  const int n = std::max(rows, cols);
  double finite_max = 0;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c)
      if (std::isfinite(cost_in(r, c)) && cost_in(r, c) < forbidden)
        finite_max = std::max(finite_max, std::abs(cost_in(r, c)));
  const double big = (finite_max + 1.0) * (n + 1);
  Eigen::MatrixXd a = Eigen::MatrixXd::Constant(n, n, big);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c)
      if (std::isfinite(cost_in(r, c)) && cost_in(r, c) < forbidden) a(r, c) = cost_in(r, c);

  // Potentials u (rows), v (cols), 1-based with a virtual column 0 (e-maxx formulation).
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> u(n + 1, 0), v(n + 1, 0), minv(n + 1);
  std::vector<int> p(n + 1, 0), way(n + 1, 0);
  std::vector<char> used(n + 1);
  for (int i = 1; i <= n; ++i) {
    p[0] = i;
    int j0 = 0;
    std::fill(minv.begin(), minv.end(), inf);
    std::fill(used.begin(), used.end(), 0);
    do {
      used[j0] = 1;
      const int i0 = p[j0];
      double delta = inf;
      int j1 = 0;
      for (int j = 1; j <= n; ++j) {
        if (used[j]) continue;
        const double cur = a(i0 - 1, j - 1) - u[i0] - v[j];
        if (cur < minv[j]) {
          minv[j] = cur;
          way[j] = j0;
        }
        if (minv[j] < delta) {
          delta = minv[j];
          j1 = j;
        }
      }
      for (int j = 0; j <= n; ++j) {
        if (used[j]) {
          u[p[j]] += delta;
          v[j] -= delta;
        } else {
          minv[j] -= delta;
        }
      }
      j0 = j1;
    } while (p[j0] != 0);
    do {
      const int j1 = way[j0];
      p[j0] = p[j1];
      j0 = j1;
    } while (j0);
  }
  for (int j = 1; j <= n; ++j) {
    const int r = p[j] - 1, c = j - 1;
    if (r < rows && c < cols && std::isfinite(cost_in(r, c)) && cost_in(r, c) < forbidden)
      result[std::size_t(r)] = c;
  }
  return result;
}

}  // namespace fieldlidar::people
