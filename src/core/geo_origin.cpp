#include "fieldlidar/core/geo_origin.hpp"

#include <charconv>
#include <cmath>
#include <numbers>
#include <vector>

#include "fieldlidar/core/error.hpp"

namespace fieldlidar {

GeoOrigin parse_geo_origin(const std::string& text, const std::string& what) {
  std::vector<double> v;
  std::size_t start = 0;
  while (start <= text.size()) {
    const auto comma = std::min(text.find(',', start), text.size());
    double x = 0;
    const char* b = text.data() + start;
    const char* e = text.data() + comma;
    const auto [p, ec] = std::from_chars(b, e, x);
    if (ec != std::errc() || p != e || !std::isfinite(x))
      throw Error(what + ": '" + text + "' is not LAT,LON[,HEADING_DEG] (degrees)");
    v.push_back(x);
    start = comma + 1;
  }
  if (v.size() < 2 || v.size() > 3)
    throw Error(what + ": '" + text + "' is not LAT,LON[,HEADING_DEG] (degrees)");
  GeoOrigin o;
  o.lat_deg = v[0];
  o.lon_deg = v[1];
  if (v.size() == 3) o.heading_deg = v[2];
  if (std::abs(o.lat_deg) > 89)
    throw Error(what + ": latitude " + std::to_string(o.lat_deg) + " is not in [-89, 89]");
  if (std::abs(o.lon_deg) > 180)
    throw Error(what + ": longitude " + std::to_string(o.lon_deg) + " is not in [-180, 180]");
  if (std::abs(o.heading_deg) > 360)
    throw Error(what + ": heading " + std::to_string(o.heading_deg) + " is not in [-360, 360]");
  return o;
}

Eigen::Vector2d local_to_lon_lat(const Eigen::Vector2d& xy_m, const GeoOrigin& origin) {
  constexpr double kA = 6378137.0;          // WGS84 semi-major axis (m)
  constexpr double kE2 = 6.69437999014e-3;  // first eccentricity squared
  constexpr double kDeg = std::numbers::pi / 180;
  // Local +x points along the compass bearing `heading`: east = sin, north = cos.
  const double h = origin.heading_deg * kDeg;
  const Eigen::Vector2d ex(std::sin(h), std::cos(h));   // +x in (east, north)
  const Eigen::Vector2d ey(-std::cos(h), std::sin(h));  // +y: 90 deg counter-clockwise of +x
  const Eigen::Vector2d en = xy_m.x() * ex + xy_m.y() * ey;
  const double lat = origin.lat_deg * kDeg;
  const double s2 = std::sin(lat) * std::sin(lat);
  const double meridian = kA * (1 - kE2) / std::pow(1 - kE2 * s2, 1.5);  // north-south radius
  const double prime = kA / std::sqrt(1 - kE2 * s2);                     // east-west radius
  return {origin.lon_deg + en.x() / (prime * std::cos(lat)) / kDeg,
          origin.lat_deg + en.y() / meridian / kDeg};
}

}  // namespace fieldlidar
