// The greenhouse scene of seed 002: rows of benches and raised beds with plants, posts, walls and
// roof trusses, narrow aisles; the robot drives the aisles in a serpentine.

#include <cmath>
#include <random>
#include <stdexcept>

#include "fieldlidar/sim/scenes.hpp"

namespace fieldlidar::sim {

Scene make_greenhouse_scene(const GreenhouseConfig& cfg, std::uint64_t seed) {
  if (cfg.rows < 1 || !(cfg.length_m > 8) || !(cfg.aisle_width_m > 0.5))
    throw std::invalid_argument(
        "GreenhouseConfig: need rows >= 1, length_m > 8, aisle_width_m > 0.5");
  std::mt19937_64 rng(seed * 104729 + 2);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  const double margin = 0.3;  // between the outer aisles and the side walls
  const double width =
      2 * margin + cfg.rows * cfg.bench_width_m + (cfg.rows + 1) * cfg.aisle_width_m;
  const double L = cfg.length_m;
  // Concrete floor with a 0.3 % drainage fall across the house.
  Scene scene(SceneKind::kGreenhouse,
              HeightField({-3.0, -3.0}, {L + 3.0, width + 3.0}, 0.5,
                          [](double, double y) { return -0.003 * y; }),
              seed);
  scene.set_sensor_height_m(0.8);
  scene.set_robot_speed_m_s(0.6);
  const auto structure = make_label(LabelClass::kStructure);
  const auto vegetation = make_label(LabelClass::kVegetation);
  const double H = cfg.wall_height_m, ridge = H + 1.5;

  // Side and end walls (cladding), a door gap in the x = 0 end wall.
  scene.add_mesh(make_aabb({-0.1, -0.1, -0.1}, {L + 0.1, 0.0, H}, structure));
  scene.add_mesh(make_aabb({-0.1, width, -0.1}, {L + 0.1, width + 0.1, H}, structure));
  scene.add_mesh(make_aabb({L, 0.0, -0.1}, {L + 0.1, width, H}, structure));
  scene.add_mesh(make_aabb({-0.1, 0.0, -0.1}, {0.0, 0.4 * width, H}, structure));
  scene.add_mesh(make_aabb({-0.1, 0.4 * width + 1.2, -0.1}, {0.0, width, H}, structure));
  // Posts along both walls and a gable truss over each pair, every post_spacing_m.
  for (double x = 0.0; x <= L + 1e-6; x += cfg.post_spacing_m) {
    for (double y : {0.1, width - 0.1})
      scene.add_mesh(make_aabb({x - 0.04, y - 0.04, -0.1}, {x + 0.04, y + 0.04, H}, structure));
    scene.add_mesh(make_aabb({x - 0.03, 0.0, H - 0.06}, {x + 0.03, width, H}, structure));  // tie
    scene.add_mesh(make_cylinder({x, 0.0, H}, {x, width / 2, ridge}, 0.04, 0.04, 6, structure));
    scene.add_mesh(make_cylinder({x, width, H}, {x, width / 2, ridge}, 0.04, 0.04, 6, structure));
    scene.add_mesh(
        make_cylinder({x, width / 2, H}, {x, width / 2, ridge}, 0.03, 0.03, 6, structure));
  }
  // Roof glazing: two 2 cm slabs from the eaves to the ridge.
  const double slope_len = std::hypot(width / 2, ridge - H);
  const double slope_angle = std::atan2(ridge - H, width / 2);
  for (int side : {-1, 1}) {
    Pose T = Pose::Identity();
    T.translation() =
        Eigen::Vector3d(L / 2, side < 0 ? width / 4 : 3 * width / 4, (H + ridge) / 2 + 0.05);
    T.linear() =
        Eigen::AngleAxisd(-side * slope_angle, Eigen::Vector3d::UnitX()).toRotationMatrix();
    scene.add_mesh(make_box(T, {L + 0.2, slope_len, 0.02}, structure));
  }

  // Rows: benches (tabletop on legs, potted plants) alternate with raised beds (soil, tall plants).
  const double x0 = 2.5, x1 = L - 2.5;
  for (int r = 0; r < cfg.rows; ++r) {
    const double y0 = margin + cfg.aisle_width_m + r * (cfg.bench_width_m + cfg.aisle_width_m);
    const double y1 = y0 + cfg.bench_width_m;
    const bool bench = r % 2 == 0;
    const double top = bench ? 0.8 : 0.4;
    if (bench) {
      scene.add_mesh(make_aabb({x0, y0, 0.74}, {x1, y1, 0.8}, structure));
      for (double x = x0 + 0.1; x <= x1; x += 1.5)
        for (double y : {y0 + 0.1, y1 - 0.1})
          scene.add_mesh(
              make_aabb({x - 0.025, y - 0.025, -0.05}, {x + 0.025, y + 0.025, 0.74}, structure));
    } else {
      scene.add_mesh(make_aabb({x0, y0, -0.05}, {x1, y1, 0.4}, structure));
    }
    const int plants = static_cast<int>(cfg.plant_density_per_m2 * (x1 - x0) * (y1 - y0));
    for (int k = 0; k < plants; ++k) {
      const Eigen::Vector3d c(x0 + 0.15 + (x1 - x0 - 0.3) * uni(rng),
                              y0 + 0.15 + (y1 - y0 - 0.3) * uni(rng), top);
      const double rr = bench ? 0.08 + 0.08 * uni(rng) : 0.12 + 0.1 * uni(rng);
      const double hh = bench ? rr : 0.3 + 0.5 * uni(rng);
      scene.add_mesh(
          make_blob(c + Eigen::Vector3d(0, 0, hh), {rr, rr, hh}, 0.25, rng, vegetation, 4, 6));
    }
  }
  // Serpentine through the aisles, turning in the headlands.
  std::vector<Eigen::Vector2d> route;
  for (int a = 0; a <= cfg.rows; ++a) {
    const double y = margin + a * (cfg.bench_width_m + cfg.aisle_width_m) + cfg.aisle_width_m / 2;
    const bool forward = a % 2 == 0;
    route.emplace_back(forward ? 1.2 : L - 1.2, y);
    route.emplace_back(forward ? L - 1.2 : 1.2, y);
  }
  scene.set_robot_route(route, false);
  return scene;
}

}  // namespace fieldlidar::sim
