#pragma once
/// \file A Grid2D layer as a GeoTIFF (one Float32 band, NaN = no data), georeferenced by the
/// grid's placement, for GIS tools (QGIS, gdalinfo, rasterio). GDAL stays private to io/.

#include <filesystem>
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

/// A one-band north-up GeoTIFF with square pixels (as encode_geotiff writes it) as a grid of one
/// layer named `layer`: placed by the geotransform (origin at its lower-left corner), its
/// no-data value and non-finite values NaN; `description`, when given, receives the band's
/// description (encode_geotiff writes the layer's name there; empty when none). `name` names the
/// source in errors. Throws fieldlidar::Error naming it when the bytes are no raster GDAL reads,
/// the raster has other than one band, or it is rotated or its pixels are not square.
Grid2D decode_geotiff(const std::string& bytes, const std::string& layer,
                      const std::string& name = "geotiff", std::string* description = nullptr);

/// The same, read from a file (errors name the file; a missing file is an error).
Grid2D read_geotiff(const std::filesystem::path& path, const std::string& layer,
                    std::string* description = nullptr);

}  // namespace fieldlidar::io
