// Trunk landmarks of two scans matched by the geometric consistency of landmark pairs: candidate
// pairs near each other under the prior and of similar DBH, then the largest set whose mutual
// distances agree (greedy clique of the consistency graph).
#include <algorithm>
#include <cmath>

#include "fieldlidar/forest/tracking.hpp"

namespace fieldlidar::forest {

std::vector<TrunkLandmark> landmarks_of(std::span<const Tree> trees, double dbh_height_m) {
  std::vector<TrunkLandmark> out;
  out.reserve(trees.size());
  for (const auto& t : trees) out.push_back({t.at_height(dbh_height_m), t.axis, t.dbh_m});
  return out;
}

std::vector<std::pair<std::size_t, std::size_t>> associate_trunks(
    std::span<const TrunkLandmark> reference, std::span<const TrunkLandmark> current,
    const Pose& prior, const AssociationConfig& config) {
  struct Candidate {
    std::size_t ref, cur;
    int degree = 0;
  };
  std::vector<Candidate> cands;
  std::vector<Eigen::Vector2d> moved(current.size());
  for (std::size_t j = 0; j < current.size(); ++j) moved[j] = (prior * current[j].point).head<2>();
  for (std::size_t i = 0; i < reference.size(); ++i)
    for (std::size_t j = 0; j < current.size(); ++j) {
      const double tol = config.dbh_tolerance_m + 0.3 * reference[i].dbh_m;
      if ((reference[i].point.head<2>() - moved[j]).norm() <= config.gate_m &&
          std::abs(reference[i].dbh_m - current[j].dbh_m) <= tol)
        cands.push_back({i, j});
    }
  const std::size_t n = cands.size();
  auto agree = [&](const Candidate& a, const Candidate& b) {
    if (a.ref == b.ref || a.cur == b.cur) return false;
    const double dr = (reference[a.ref].point - reference[b.ref].point).head<2>().norm();
    const double dc = (current[a.cur].point - current[b.cur].point).head<2>().norm();
    return std::abs(dr - dc) <= config.pair_tolerance_m;
  };
  std::vector<char> ok(n * n, 0);
  for (std::size_t a = 0; a < n; ++a)
    for (std::size_t b = a + 1; b < n; ++b)
      if (agree(cands[a], cands[b])) {
        ok[a * n + b] = ok[b * n + a] = 1;
        ++cands[a].degree;
        ++cands[b].degree;
      }
  std::vector<std::size_t> order(n);
  for (std::size_t k = 0; k < n; ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(),
                   [&](auto a, auto b) { return cands[a].degree > cands[b].degree; });
  // Greedy clique from each of the best-connected seeds; the largest one wins.
  std::vector<std::size_t> best;
  for (std::size_t s = 0; s < std::min<std::size_t>(n, 5); ++s) {
    std::vector<std::size_t> clique{order[s]};
    for (auto k : order) {
      if (k == order[s]) continue;
      bool all = true;
      for (auto m : clique) all &= bool(ok[k * n + m]);
      if (all) clique.push_back(k);
    }
    if (clique.size() > best.size()) best = std::move(clique);
  }
  std::vector<std::pair<std::size_t, std::size_t>> out;
  if (best.size() < config.min_matches) return out;
  for (auto k : best) out.emplace_back(cands[k].ref, cands[k].cur);
  return out;
}

}  // namespace fieldlidar::forest
