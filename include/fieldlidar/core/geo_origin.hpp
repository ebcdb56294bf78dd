#pragma once
/// \file Placing a local metric frame on the Earth: local x-y (m) to WGS84 longitude/latitude
/// (deg) through the local tangent plane at a known origin, for outputs that must be in WGS84
/// (GeoJSON, RFC 7946).
///
/// Accuracy: the tangent plane uses the WGS84 meridian and prime-vertical radii of curvature at
/// the origin's latitude. Against the exact ENU -> ECEF -> geodetic conversion the horizontal
/// error grows with the square of the distance d from the origin, about d^2 tan(lat) / (2 R):
/// at 48 deg latitude 1.0 mm at 100 m, 0.10 m at 1 km, 2.4 m at 5 km (at 60 deg: 1.5 mm,
/// 0.15 m, 3.8 m). Good for a field or a plot, not for tens of kilometres (use a projection).
/// Heights are ignored (x-y only).

#include <string>

#include <Eigen/Core>

namespace fieldlidar {

struct GeoOrigin {
  double lat_deg = 0;       ///< WGS84 latitude of the local frame's origin, [-89, 89]
  double lon_deg = 0;       ///< WGS84 longitude of the origin, [-180, 180]
  double heading_deg = 90;  ///< compass bearing of the local +x axis (90: x east, y north)
};

/// Parses "LAT,LON" or "LAT,LON,HEADING_DEG"; throws fieldlidar::Error naming `what` (the option)
/// and the value when it is malformed or out of range.
GeoOrigin parse_geo_origin(const std::string& text, const std::string& what);

/// Local x-y (m) to (longitude, latitude) in degrees.
Eigen::Vector2d local_to_lon_lat(const Eigen::Vector2d& xy_m, const GeoOrigin& origin);

}  // namespace fieldlidar
