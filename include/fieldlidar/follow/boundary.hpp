#pragma once
/// \file Recording the lawn boundary while following (seed 000, step 8): record while following,
/// pause while stopped for safety or loss, close on the stop command by joining the end to the
/// start, simplify, check for self-intersections, and format as GeoJSON / CSV.
///
/// Frame: a local metric frame, x east-like and y north-like as the robot's world/odometry frame
/// (m). GeoJSON coordinates are WGS84 [longitude, latitude] when the frame's GeoOrigin is given
/// (RFC 7946; the local metres stay in "properties.local_coordinates_m"), else [x, y] in metres
/// in that frame (the file says so in "properties.coordinates").

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "fieldlidar/core/geo_origin.hpp"

namespace fieldlidar::follow {

struct BoundaryConfig {
  double record_spacing_m = 0.05;      ///< a point is recorded when this far from the last one
  double simplify_tolerance_m = 0.03;  ///< Douglas-Peucker tolerance of the closed polygon
  double min_vertex_spacing_m = 0.02;  ///< vertices nearer than this to the previous are dropped
};

/// A self-intersection: edges i and j (edge i joins vertex i to i+1, cyclic) cross at `point_m`.
struct SelfIntersection {
  std::size_t edge_a = 0, edge_b = 0;
  Eigen::Vector2d point_m = Eigen::Vector2d::Zero();
};

struct BoundaryPolygon {
  std::vector<Eigen::Vector2d> vertices;  ///< closed implicitly (last joins first), no repeat
  std::vector<SelfIntersection> self_intersections;
  double area_m2 = 0;  ///< |shoelace area|
  double perimeter_m = 0;
  std::size_t raw_points = 0;  ///< recorded points before simplification
  /// False when the recording ended without the stop command (a time limit): the vertices are
  /// an open path, not a ring.
  bool closed = true;
};

/// What a recorded boundary is, for writing it as a valid geometry.
enum class BoundaryShape { kPolygon, kOpenPath, kTooFewVertices, kSelfIntersecting };
BoundaryShape boundary_shape(const BoundaryPolygon& polygon);
std::string to_string(BoundaryShape shape);

class BoundaryRecorder {
 public:
  explicit BoundaryRecorder(const BoundaryConfig& config = {}) : config_(config) {}
  /// Records `p_m` (world frame) when `following` is true; a false call pauses the recording.
  void record(const Eigen::Vector2d& p_m, bool following);
  const std::vector<Eigen::Vector2d>& points() const { return points_; }
  /// Length recorded so far (m).
  double length_m() const { return length_m_; }
  /// The stop command: joins the end to the start, simplifies, and checks the polygon.
  BoundaryPolygon close() const;

 private:
  BoundaryConfig config_;
  std::vector<Eigen::Vector2d> points_;
  double length_m_ = 0;
};

/// Douglas-Peucker on a closed ring plus dropping vertices closer than `min_spacing_m`.
std::vector<Eigen::Vector2d> simplify_closed(const std::vector<Eigen::Vector2d>& ring,
                                             double tolerance_m, double min_spacing_m);
/// Every pair of non-adjacent edges of the closed ring that cross or touch.
std::vector<SelfIntersection> find_self_intersections(const std::vector<Eigen::Vector2d>& ring);
/// Signed shoelace area (CCW positive).
double signed_area(const std::vector<Eigen::Vector2d>& ring);

/// GeoJSON FeatureCollection with one feature: a Polygon (the ring repeated at its end, CCW) when
/// boundary_shape() is kPolygon, else a LineString (an open path as recorded; a ring that crosses
/// itself closed by repeating its first vertex), never an invalid Polygon. The frame, shape, area,
/// perimeter and self-intersections are in the properties. With `origin`, coordinates are WGS84
/// longitude/latitude (9 decimals) and the metres are kept in the properties.
std::string boundary_geojson(const BoundaryPolygon& polygon, const std::string& frame_id,
                             const std::optional<GeoOrigin>& origin = std::nullopt);
/// CSV: `index,x,y` per vertex (m).
std::string boundary_csv(const BoundaryPolygon& polygon);

/// Distances between a closed polygon and a closed reference polyline, both densely sampled
/// (`step_m`): mean distance from the polygon to the reference, and the symmetric Hausdorff.
struct PolygonDistance {
  double mean_m = 0;
  double hausdorff_m = 0;
};
PolygonDistance compare_closed(const std::vector<Eigen::Vector2d>& polygon,
                               const std::vector<Eigen::Vector2d>& reference, double step_m = 0.05);
/// Distance from a point to a closed polyline.
double distance_to_closed(const Eigen::Vector2d& p, const std::vector<Eigen::Vector2d>& ring);

}  // namespace fieldlidar::follow
