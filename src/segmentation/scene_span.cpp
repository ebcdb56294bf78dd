// Whether a cloud spans more than any scene a ground robot maps (another unit than metres, stray
// far points): the ground methods refuse it before sizing grids from its extent.
#include <cstdio>
#include <optional>
#include <string>

#include "fieldlidar/segmentation/ground.hpp"

namespace fieldlidar::segmentation {

std::optional<std::string> implausible_span(const PointCloud& cloud) {
  return implausible_span(compute_bounds(cloud));
}

std::optional<std::string> implausible_span(const Bounds3& b) {
  if (b.empty()) return std::nullopt;
  const Eigen::Vector3d span = b.max - b.min;
  // Compared negated so that a span of inf (or NaN) is refused too.
  if (!(span.maxCoeff() > kMaxSceneSpanM) && span.allFinite()) return std::nullopt;
  char text[200];
  std::snprintf(text, sizeof text,
                "the points span %.3g x %.3g x %.3g m, more than %.0e m: coordinates in another "
                "unit than metres, or stray far points?",
                span.x(), span.y(), span.z(), kMaxSceneSpanM);
  return std::string(text);
}

}  // namespace fieldlidar::segmentation
