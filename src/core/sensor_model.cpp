#include "fieldlidar/core/sensor_model.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace fieldlidar {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

std::vector<double> uniform_deg(double lo_deg, double hi_deg, int n) {
  std::vector<double> out(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) out[i] = (lo_deg + (hi_deg - lo_deg) * i / (n - 1)) * kDeg;
  return out;
}

}  // namespace

double SensorModel::min_altitude_rad() const {
  return beam_altitudes_rad.empty() ? 0.0 : beam_altitudes_rad.front();
}
double SensorModel::ground_reach_m(double height_m) const {
  const double lowest = min_altitude_rad();
  return lowest < 0 ? height_m / std::tan(-lowest) : std::numeric_limits<double>::infinity();
}
double SensorModel::max_altitude_rad() const {
  return beam_altitudes_rad.empty() ? 0.0 : beam_altitudes_rad.back();
}

double SensorModel::vertical_resolution_rad() const {
  if (rings() < 2) return 0.0;
  return (max_altitude_rad() - min_altitude_rad()) / static_cast<double>(rings() - 1);
}

std::size_t SensorModel::nearest_ring(double altitude_rad) const {
  const auto& a = beam_altitudes_rad;
  if (a.empty()) return 0;
  auto it = std::lower_bound(a.begin(), a.end(), altitude_rad);
  if (it == a.end()) return a.size() - 1;
  if (it == a.begin()) return 0;
  auto prev = std::prev(it);
  return static_cast<std::size_t>((altitude_rad - *prev < *it - altitude_rad ? prev : it) -
                                  a.begin());
}

void SensorModel::validate() const {
  auto fail = [&](const std::string& what) {
    throw std::invalid_argument("sensor model '" + name + "': " + what);
  };
  if (beam_altitudes_rad.empty()) fail("beam_altitudes_rad is empty");
  if (!std::is_sorted(beam_altitudes_rad.begin(), beam_altitudes_rad.end()))
    fail("beam_altitudes_rad must be ascending (ring 0 = lowest beam)");
  for (double a : beam_altitudes_rad)
    if (!std::isfinite(a) || std::abs(a) > std::numbers::pi / 2)
      fail("a beam altitude is not in [-pi/2, pi/2]");
  if (!beam_azimuth_offsets_rad.empty() && beam_azimuth_offsets_rad.size() != rings())
    fail("beam_azimuth_offsets_rad must be empty or have one entry per ring");
  if (columns < 1 || columns > 1 << 20)
    fail("columns = " + std::to_string(columns) + " is out of range");
  if (!(horizontal_fov_rad > 0 && horizontal_fov_rad <= 2 * std::numbers::pi + 1e-9))
    fail("horizontal_fov_rad must be in (0, 2*pi]");
  if (!(rotation_rate_hz > 0 && rotation_rate_hz < 1000))
    fail("rotation_rate_hz must be in (0, 1000)");
  if (!(min_range_m >= 0 && max_range_m > min_range_m && std::isfinite(max_range_m)))
    fail("need 0 <= min_range_m < max_range_m < inf");
  if (!(range_accuracy_m >= 0) || !std::isfinite(range_accuracy_m))
    fail("range_accuracy_m must be >= 0");
}

SensorModel SensorModel::from_beam_angles(std::string name, std::vector<double> altitudes_rad,
                                          int columns, double rotation_rate_hz, double min_range_m,
                                          double max_range_m) {
  SensorModel m;
  m.name = std::move(name);
  std::sort(altitudes_rad.begin(), altitudes_rad.end());
  m.beam_altitudes_rad = std::move(altitudes_rad);
  m.columns = columns;
  m.rotation_rate_hz = rotation_rate_hz;
  m.min_range_m = min_range_m;
  m.max_range_m = max_range_m;
  m.validate();
  return m;
}

SensorModel SensorModel::vlp16() {
  // Velodyne VLP-16: 16 beams, -15..+15 deg in 2 deg steps, 0.2 deg at 10 Hz, 100 m.
  auto m = from_beam_angles("vlp16", uniform_deg(-15.0, 15.0, 16), 1800, 10.0, 0.4, 100.0);
  m.range_accuracy_m = 0.03;
  return m;
}

SensorModel SensorModel::vlp32c() {
  // Velodyne VLP-32C (Ultra Puck) published elevation table, non-uniform, -25..+15 deg.
  std::vector<double> deg = {-25,    -1,    -1.667, -15.639, -11.31, 0,     -0.667, -8.843,
                             -7.254, 0.333, -0.333, -6.148,  -5.333, 1.333, 0.667,  -4,
                             -4.667, 1.667, 1,      -3.667,  -3.333, 3.333, 2.333,  -2.667,
                             -3,     7,     4.667,  -2.333,  -2,     15,    10.333, -1.333};
  for (auto& d : deg) d *= kDeg;
  auto m = from_beam_angles("vlp32c", deg, 1800, 10.0, 0.4, 200.0);
  m.range_accuracy_m = 0.03;
  return m;
}

SensorModel SensorModel::hdl32e() {
  // Velodyne HDL-32E: 32 beams, -30.67..+10.67 deg in 1.33 deg steps, 0.16 deg at 10 Hz.
  auto m = from_beam_angles("hdl32e", uniform_deg(-30.67, 10.67, 32), 2170, 10.0, 1.0, 100.0);
  m.range_accuracy_m = 0.02;
  return m;
}

SensorModel SensorModel::hdl64e() {
  // Velodyne HDL-64E S2: upper block 32 beams +2..-8.33 deg (1/3 deg), lower block 32 beams
  // -8.83..-24.33 deg (1/2 deg); 0.17 deg horizontal at 10 Hz, 120 m.
  auto upper = uniform_deg(-8.33, 2.0, 32);
  auto lower = uniform_deg(-24.33, -8.83, 32);
  upper.insert(upper.end(), lower.begin(), lower.end());
  auto m = from_beam_angles("hdl64e", upper, 2083, 10.0, 0.9, 120.0);
  m.range_accuracy_m = 0.02;
  return m;
}

SensorModel SensorModel::os1_64() {
  // Ouster OS1-64 (uniform, 33.2 deg vertical field), 1024 columns at 10 Hz, 120 m.
  auto m = from_beam_angles("os1-64", uniform_deg(-16.6, 16.6, 64), 1024, 10.0, 0.3, 120.0);
  m.range_accuracy_m = 0.03;
  m.beam_origin_offset_m = 0.015806;
  return m;
}

SensorModel SensorModel::os1_128() {
  // Ouster OS1-128 (uniform, 45 deg vertical field), 1024 columns at 10 Hz, 120 m.
  auto m = from_beam_angles("os1-128", uniform_deg(-22.5, 22.5, 128), 1024, 10.0, 0.3, 120.0);
  m.range_accuracy_m = 0.03;
  m.beam_origin_offset_m = 0.015806;
  return m;
}

SensorModel SensorModel::os2_128() {
  // Ouster OS2-128 (uniform, 22.5 deg vertical field), long range.
  auto m = from_beam_angles("os2-128", uniform_deg(-11.25, 11.25, 128), 1024, 10.0, 0.8, 240.0);
  m.range_accuracy_m = 0.03;
  m.beam_origin_offset_m = 0.01326;
  return m;
}

SensorModel SensorModel::tilting_2d(int planes, double min_tilt_rad, double max_tilt_rad,
                                    int columns, double scan_fov_rad) {
  if (planes < 2) throw std::invalid_argument("tilting_2d: planes must be >= 2");
  std::vector<double> alt(static_cast<std::size_t>(planes));
  for (int i = 0; i < planes; ++i)
    alt[i] = min_tilt_rad + (max_tilt_rad - min_tilt_rad) * i / (planes - 1);
  auto m = from_beam_angles("tilting2d", alt, columns, 0.5, 0.1, 30.0);
  m.kind = Kind::kTilting2D;
  m.horizontal_fov_rad = scan_fov_rad;
  m.range_accuracy_m = 0.01;
  m.validate();
  return m;
}

SensorModel SensorModel::laser_2d(int columns, double scan_fov_rad, double rate_hz,
                                  double max_range_m) {
  auto m = from_beam_angles("laser2d", {0.0}, columns, rate_hz, 0.05, max_range_m);
  m.kind = Kind::kPlanar2D;
  m.horizontal_fov_rad = scan_fov_rad;
  m.range_accuracy_m = 0.01;
  m.validate();
  return m;
}

std::optional<SensorModel> SensorModel::preset(const std::string& name) {
  if (name == "vlp16") return vlp16();
  if (name == "vlp32c") return vlp32c();
  if (name == "hdl32e") return hdl32e();
  if (name == "hdl64e") return hdl64e();
  if (name == "os1-64" || name == "os1_64") return os1_64();
  if (name == "os1-128" || name == "os1_128") return os1_128();
  if (name == "os2-128" || name == "os2_128") return os2_128();
  if (name == "tilting2d") return tilting_2d();
  if (name == "laser2d") return laser_2d();
  return std::nullopt;
}

std::vector<std::string> SensorModel::preset_names() {
  return {"vlp16",   "vlp32c",  "hdl32e",    "hdl64e", "os1-64",
          "os1-128", "os2-128", "tilting2d", "laser2d"};
}

}  // namespace fieldlidar
