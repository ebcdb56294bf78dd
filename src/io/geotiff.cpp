/// Grid2D layer -> GeoTIFF bytes through GDAL's GTiff driver on an in-memory file.
#include "fieldlidar/io/geotiff.hpp"

#include <atomic>
#include <cmath>
#include <limits>
#include <mutex>
#include <vector>

#include <cpl_vsi.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include "fieldlidar/core/error.hpp"

namespace fieldlidar::io {

std::string encode_geotiff(const Grid2D& grid, const std::string& layer,
                           const GeoTiffConfig& config) {
  const GridGeometry& g = grid.geometry();
  if (g.cell_count() == 0) throw Error("geotiff: layer '" + layer + "': the grid is empty");
  if (!grid.has_layer(layer)) throw Error("geotiff: no layer '" + layer + "' in the grid");
  static std::once_flag registered;
  std::call_once(registered, [] { GDALRegister_GTiff(); });
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GTiff");
  if (!driver) throw Error("geotiff: GDAL has no GTiff driver");
  static std::atomic<int> serial{0};
  const std::string path = "/vsimem/fieldlidar_" + std::to_string(serial++) + ".tif";
  char** options = nullptr;
  options = CSLSetNameValue(options, "COMPRESS", "DEFLATE");
  GDALDataset* ds = driver->Create(path.c_str(), g.width, g.height, 1, GDT_Float32, options);
  CSLDestroy(options);
  if (!ds) throw Error("geotiff: GDAL could not create the raster for layer '" + layer + "'");
  const Eigen::Vector2d origin = g.origin_m + config.origin_offset_m;
  double transform[6] = {origin.x(), g.resolution_m, 0.0, origin.y() + g.height * g.resolution_m,
                         0.0,        -g.resolution_m};
  ds->SetGeoTransform(transform);
  if (config.epsg > 0) {
    OGRSpatialReference srs;
    if (srs.importFromEPSG(config.epsg) == OGRERR_NONE) ds->SetSpatialRef(&srs);
  }
  GDALRasterBand* band = ds->GetRasterBand(1);
  band->SetNoDataValue(std::numeric_limits<double>::quiet_NaN());
  band->SetDescription(layer.c_str());
  const auto values = grid.layer(layer);
  std::vector<float> row(std::size_t(g.width));
  CPLErr err = CE_None;
  for (int r = 0; r < g.height && err == CE_None; ++r) {
    const int iy = g.height - 1 - r;  // row 0 is the top (largest y)
    for (int ix = 0; ix < g.width; ++ix) row[std::size_t(ix)] = values[g.linear_index(ix, iy)];
    err = band->RasterIO(GF_Write, 0, r, g.width, 1, row.data(), g.width, 1, GDT_Float32, 0, 0);
  }
  GDALClose(ds);
  vsi_l_offset size = 0;
  GByte* bytes = VSIGetMemFileBuffer(path.c_str(), &size, FALSE);
  std::string out = bytes ? std::string(reinterpret_cast<const char*>(bytes), size) : std::string();
  VSIUnlink(path.c_str());
  if (err != CE_None || out.empty())
    throw Error("geotiff: GDAL failed to write layer '" + layer + "'");
  return out;
}

}  // namespace fieldlidar::io
