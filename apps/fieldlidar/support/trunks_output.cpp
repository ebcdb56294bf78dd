// trees.csv, trees.geojson and the top-down pictures of `fieldlidar trunks`.
#include "support/trunks_output.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "support/canvas.hpp"

namespace fieldlidar::app {
namespace {

// Height of each point above the ground: the lowest ground return of its 1 m cell (or of the
// nearest cells around it); NaN where no ground is near.
std::vector<float> height_above_ground(const PointCloud& cloud,
                                       const std::vector<std::uint8_t>& ground) {
  std::unordered_map<std::int64_t, float> low;
  auto key = [](float x, float y) {
    return (std::int64_t(std::floor(x)) << 32) ^ (std::int64_t(std::floor(y)) & 0xffffffff);
  };
  for (std::size_t i = 0; i < cloud.size(); ++i)
    if (ground[i] && cloud.points[i].is_valid()) {
      auto [it, fresh] = low.emplace(key(cloud.points[i].x, cloud.points[i].y), cloud.points[i].z);
      if (!fresh) it->second = std::min(it->second, cloud.points[i].z);
    }
  std::vector<float> h(cloud.size(), std::numeric_limits<float>::quiet_NaN());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const auto& p = cloud.points[i];
    if (!p.is_valid()) continue;
    for (int r = 0; r <= 2 && std::isnan(h[i]); ++r)
      for (int dx = -r; dx <= r; ++dx)
        for (int dy = -r; dy <= r; ++dy) {
          auto it = low.find(key(p.x + float(dx), p.y + float(dy)));
          if (it != low.end() && (std::isnan(h[i]) || p.z - it->second < h[i]))
            h[i] = p.z - it->second;
        }
  }
  return h;
}

// A stem's id; "?" after it when its diameter is a guess (drawn thin, empty in trees.csv).
std::string label(const forest::Tree& t) {
  return std::to_string(t.id) + (t.dbh_uncertain ? "?" : "");
}

}  // namespace

std::string trees_csv(const std::vector<forest::Tree>& trees, const Eigen::Vector3d& origin) {
  std::string s =
      "id,x_m,y_m,z_base_m,dbh_m,axis_x,axis_y,axis_z,height_seen_m,arc_deg,"
      "residual_m,observations,dbh_uncertain\n";
  for (const auto& t : trees) {
    const Eigen::Vector3d b = t.base_m + origin;
    // A diameter no scan line measured (dbh_uncertain) is left empty: the stem's position
    // stands, its diameter is not an inventory figure.
    const std::string dbh = t.dbh_uncertain ? "" : fmt::format("{:.4f}", t.dbh_m);
    s += fmt::format("{},{:.3f},{:.3f},{:.3f},{},{:.4f},{:.4f},{:.4f},{:.2f},{:.1f},{:.4f},{},{}\n",
                     t.id, b.x(), b.y(), b.z(), dbh, t.axis.x(), t.axis.y(), t.axis.z(),
                     t.z_max_seen_m - t.z_min_seen_m, t.arc_deg, t.residual_m, t.observations,
                     int(t.dbh_uncertain));
  }
  return s;
}

std::string trees_geojson(const std::vector<forest::Tree>& trees, const Eigen::Vector3d& origin) {
  nlohmann::json fc = {{"type", "FeatureCollection"}, {"features", nlohmann::json::array()}};
  for (const auto& t : trees) {
    const Eigen::Vector3d b = t.base_m + origin;
    fc["features"].push_back(
        {{"type", "Feature"},
         {"geometry", {{"type", "Point"}, {"coordinates", {b.x(), b.y(), b.z()}}}},
         {"properties",
          {{"id", t.id},
           {"dbh_m", t.dbh_uncertain ? nlohmann::json() : nlohmann::json(t.dbh_m)},
           {"height_seen_m", t.z_max_seen_m - t.z_min_seen_m},
           {"arc_deg", t.arc_deg},
           {"residual_m", t.residual_m},
           {"observations", t.observations},
           {"ground_found", t.ground_found},
           {"dbh_uncertain", t.dbh_uncertain}}}});
  }
  return fc.dump(1) + "\n";
}

void draw_trees(const PointCloud& cloud, const std::vector<std::uint8_t>& ground,
                const std::vector<forest::Tree>& trees, const std::filesystem::path& path,
                bool force) {
  const Bounds3 b = compute_bounds(cloud);
  if (b.empty()) return;
  TopDownCanvas canvas(b.min.head<2>(), b.max.head<2>());
  const auto h = height_above_ground(cloud, ground);
  const std::size_t step = std::max<std::size_t>(1, cloud.size() / 200000);
  for (std::size_t i = 0; i < cloud.size(); i += step)
    if (cloud.points[i].is_valid() && !(h[i] >= 1.2f && h[i] <= 1.4f))
      canvas.dot({cloud.points[i].x, cloud.points[i].y},
                 ground[i] ? Rgb{0.9, 0.87, 0.8} : Rgb{0.85, 0.87, 0.9}, 0.5);
  for (std::size_t i = 0; i < cloud.size(); ++i)
    if (h[i] >= 1.2f && h[i] <= 1.4f)
      canvas.dot({cloud.points[i].x, cloud.points[i].y}, {0.15, 0.15, 0.2}, 0.7);
  for (const auto& t : trees) {
    const Eigen::Vector2d c = t.at_height(1.3).head<2>();
    canvas.circle(c, t.dbh_m / 2, palette(t.id), t.dbh_uncertain ? 0.7 : 2.0);
    canvas.text(c + Eigen::Vector2d(t.dbh_m / 2 + 0.1, 0), label(t), {0, 0, 0}, 11);
  }
  canvas.title(fmt::format("trunks: {} trees", trees.size()));
  canvas.legend({{"points 1.2-1.4 m above the ground", {0.15, 0.15, 0.2}},
                 {"other points", {0.85, 0.87, 0.9}},
                 {"stem at 1.3 m (DBH; thin, id?: a guess)", palette(1)}});
  canvas.save_png(path, force);
}

void draw_slice(const PointCloud& cloud, const std::vector<forest::Tree>& trees,
                const std::filesystem::path& path, bool force) {
  const Bounds3 b = compute_bounds(cloud);
  if (b.empty()) return;
  TopDownCanvas canvas(b.min.head<2>(), b.max.head<2>());
  for (const auto& p : cloud.points)
    if (p.is_valid()) canvas.dot({p.x, p.y}, {0.15, 0.15, 0.2}, 0.7);
  for (const auto& t : trees) {
    const Eigen::Vector2d c = t.base_m.head<2>();
    canvas.circle(c, t.dbh_m / 2, palette(t.id), 1.5);
    canvas.text(c + Eigen::Vector2d(t.dbh_m / 2 + 0.02, 0), label(t), {0, 0, 0}, 11);
  }
  canvas.title(fmt::format("stem slice: {} stems", trees.size()));
  canvas.legend({{"points of the slice", {0.15, 0.15, 0.2}},
                 {"stem circle (diameter at the slice)", palette(1)}});
  canvas.save_png(path, force);
}

void draw_trunk_map(const std::vector<forest::Tree>& trees,
                    const std::vector<Eigen::Vector3d>& path, const std::filesystem::path& file,
                    bool force) {
  Eigen::Vector2d lo(1e30, 1e30), hi(-1e30, -1e30);
  for (const auto& p : path) lo = lo.cwiseMin(p.head<2>()), hi = hi.cwiseMax(p.head<2>());
  for (const auto& t : trees) {
    const Eigen::Vector2d c = t.at_height(1.3).head<2>();
    lo = lo.cwiseMin(c), hi = hi.cwiseMax(c);
  }
  if (!(lo.x() <= hi.x())) return;
  TopDownCanvas canvas(lo - Eigen::Vector2d(2, 2), hi + Eigen::Vector2d(2, 2));
  std::vector<Eigen::Vector2d> xy;
  for (const auto& p : path) xy.push_back(p.head<2>());
  canvas.polyline(xy, {0.2, 0.2, 0.2}, 2.0);
  for (const auto& t : trees) {
    const Eigen::Vector2d c = t.at_height(1.3).head<2>();
    canvas.circle(c, std::max(t.dbh_m / 2, 0.05), palette(t.id), t.dbh_uncertain ? 0.7 : 2.0);
    canvas.text(c + Eigen::Vector2d(t.dbh_m / 2 + 0.15, 0), label(t), {0, 0, 0}, 10);
  }
  canvas.title(fmt::format("trunk map: {} trees, {} scans", trees.size(), path.size()));
  canvas.legend(
      {{"driven path", {0.2, 0.2, 0.2}}, {"stem at 1.3 m (DBH; thin, id?: a guess)", palette(1)}});
  canvas.save_png(file, force);
}

}  // namespace fieldlidar::app
