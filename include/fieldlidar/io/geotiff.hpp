#pragma once
/// \file A Grid2D layer as a GeoTIFF (one Float32 band, NaN = no data), georeferenced by the
/// grid's placement, for GIS tools (QGIS, gdalinfo, rasterio). GDAL stays private to io/.

#include <string>

#include <Eigen/Core>

#include "fieldlidar/core/grid2d.hpp"

namespace fieldlidar::io {

struct GeoTiffConfig {
  /// Added to the grid's origin (a survey's cloud origin_m, so the raster sits in the file's own
  /// coordinates).
  Eigen::Vector2d origin_offset_m = Eigen::Vector2d::Zero();
  int epsg = 0;  ///< coordinate system to record; 0: none (a local metric frame)
};

/// The bytes of a GeoTIFF holding layer `layer` of `grid`: row 0 is the largest y (north up),
/// geotransform (x0, res, 0, y_max, 0, -res), no-data NaN. Throws fieldlidar::Error naming the
/// layer when it is missing or the grid is empty.
std::string encode_geotiff(const Grid2D& grid, const std::string& layer,
                           const GeoTiffConfig& config = {});

}  // namespace fieldlidar::io
