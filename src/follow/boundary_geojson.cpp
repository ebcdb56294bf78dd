// The recorded boundary as GeoJSON and CSV.

#include <cstdio>
#include <string>
#include <vector>

#include "fieldlidar/follow/boundary.hpp"

namespace fieldlidar::follow {

namespace {

std::string number_pair(const Eigen::Vector2d& v, const char* format) {
  char buf[96];
  std::snprintf(buf, sizeof buf, format, v.x(), v.y());
  return buf;
}

/// "[[x,y],[x,y],...]" of `points` (repeating the first at the end when `close` is true).
std::string coordinate_list(const std::vector<Eigen::Vector2d>& points, bool close,
                            const std::optional<GeoOrigin>& origin) {
  std::string s = "[";
  const std::size_t n = points.size() + (close && !points.empty() ? 1 : 0);
  for (std::size_t i = 0; i < n; ++i) {
    const auto& v = points[i % points.size()];
    if (i) s += ",";
    s += origin ? number_pair(local_to_lon_lat(v, *origin), "[%.9f,%.9f]")
                : number_pair(v, "[%.4f,%.4f]");
  }
  return s + "]";
}

}  // namespace

BoundaryShape boundary_shape(const BoundaryPolygon& poly) {
  if (!poly.closed) return BoundaryShape::kOpenPath;
  if (poly.vertices.size() < 3) return BoundaryShape::kTooFewVertices;
  if (!poly.self_intersections.empty()) return BoundaryShape::kSelfIntersecting;
  return BoundaryShape::kPolygon;
}

std::string to_string(BoundaryShape shape) {
  switch (shape) {
    case BoundaryShape::kPolygon:
      return "closed simple polygon";
    case BoundaryShape::kOpenPath:
      return "open path: the loop was not closed by the stop command";
    case BoundaryShape::kTooFewVertices:
      return "fewer than 3 vertices";
    case BoundaryShape::kSelfIntersecting:
      return "closed ring that crosses itself (not a valid polygon)";
  }
  return "unknown";
}

std::string boundary_geojson(const BoundaryPolygon& poly, const std::string& frame_id,
                             const std::optional<GeoOrigin>& origin) {
  const BoundaryShape shape = boundary_shape(poly);
  char buf[256];
  std::string s = "{\"type\":\"FeatureCollection\",\"features\":[{\"type\":\"Feature\",";
  s += "\"properties\":{\"name\":\"lawn boundary\",\"frame\":\"" + frame_id + "\",";
  if (origin) {
    std::snprintf(buf, sizeof buf,
                  "\"coordinates\":\"WGS84 longitude, latitude (deg) from the local frame by a "
                  "tangent plane at the origin\",\"origin\":{\"lat_deg\":%.9f,\"lon_deg\":%.9f,"
                  "\"heading_deg\":%.6f},",
                  origin->lat_deg, origin->lon_deg, origin->heading_deg);
    s += buf;
    s += "\"local_coordinates_m\":" + coordinate_list(poly.vertices, false, std::nullopt) + ",";
  } else {
    s += "\"units\":\"m\",\"coordinates\":\"local metric x-y, not WGS84 (give an origin)\",";
  }
  s +=
      "\"shape\":\"" + to_string(shape) + "\",\"closed\":" + (poly.closed ? "true" : "false") + ",";
  if (poly.closed) {
    std::snprintf(buf, sizeof buf, "\"area_m2\":%.4f,\"perimeter_m\":%.4f,\"vertices\":%zu,",
                  poly.area_m2, poly.perimeter_m, poly.vertices.size());
  } else {  // an open path has a length, no area
    double length_m = 0;
    for (std::size_t i = 1; i < poly.vertices.size(); ++i)
      length_m += (poly.vertices[i] - poly.vertices[i - 1]).norm();
    std::snprintf(buf, sizeof buf, "\"length_m\":%.4f,\"vertices\":%zu,", length_m,
                  poly.vertices.size());
  }
  s += buf;
  s += "\"self_intersections\":[";
  for (std::size_t i = 0; i < poly.self_intersections.size(); ++i) {
    const auto& x = poly.self_intersections[i];
    std::snprintf(buf, sizeof buf, "%s{\"edges\":[%zu,%zu],\"point\":[%.4f,%.4f]}", i ? "," : "",
                  x.edge_a, x.edge_b, x.point_m.x(), x.point_m.y());
    s += buf;
  }
  s += "]},\"geometry\":";
  if (shape == BoundaryShape::kPolygon)
    s += "{\"type\":\"Polygon\",\"coordinates\":[" + coordinate_list(poly.vertices, true, origin) +
         "]}";
  else  // an open path as recorded; a ring that crosses itself as a closed line
    s += "{\"type\":\"LineString\",\"coordinates\":" +
         coordinate_list(poly.vertices, shape == BoundaryShape::kSelfIntersecting, origin) + "}";
  s += "}]}\n";
  return s;
}

std::string boundary_csv(const BoundaryPolygon& poly) {
  std::string s = "index,x,y\n";
  char buf[96];
  for (std::size_t i = 0; i < poly.vertices.size(); ++i) {
    std::snprintf(buf, sizeof buf, "%zu,%.4f,%.4f\n", i, poly.vertices[i].x(),
                  poly.vertices[i].y());
    s += buf;
  }
  return s;
}

}  // namespace fieldlidar::follow
