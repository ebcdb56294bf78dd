/// Grid2D layer <-> GeoTIFF bytes through GDAL's GTiff driver on in-memory files.
#include "fieldlidar/io/geotiff.hpp"

#include <atomic>
#include <cmath>
#include <limits>
#include <mutex>
#include <vector>

#include <cpl_error.h>
#include <cpl_vsi.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/file_util.hpp"

namespace fieldlidar::io {
namespace {

/// GDAL's GTiff driver, registered once (the only driver this file uses).
void register_gtiff() {
  static std::once_flag registered;
  std::call_once(registered, [] { GDALRegister_GTiff(); });
}

/// A fresh name for an in-memory file.
std::string vsimem_path() {
  static std::atomic<int> serial{0};
  return "/vsimem/fieldlidar_" + std::to_string(serial++) + ".tif";
}

/// The raster of an in-memory copy of `bytes`, closed and unlinked on destruction.
class MemRaster {
 public:
  explicit MemRaster(const std::string& bytes) {
    register_gtiff();
    path_ = vsimem_path();
    VSILFILE* f = VSIFileFromMemBuffer(path_.c_str(),
                                       reinterpret_cast<GByte*>(const_cast<char*>(bytes.data())),
                                       vsi_l_offset(bytes.size()), FALSE);
    if (f) VSIFCloseL(f);
    CPLPushErrorHandler(CPLQuietErrorHandler);         // the error below names the problem
    const char* const drivers[] = {"GTiff", nullptr};  // a PGM or PNG is no GeoTIFF
    ds_ = static_cast<GDALDataset*>(
        GDALOpenEx(path_.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, drivers, nullptr, nullptr));
    CPLPopErrorHandler();
  }
  ~MemRaster() {
    if (ds_) GDALClose(ds_);
    VSIUnlink(path_.c_str());
  }
  MemRaster(const MemRaster&) = delete;
  MemRaster& operator=(const MemRaster&) = delete;
  GDALDataset* dataset() const { return ds_; }

 private:
  std::string path_;
  GDALDataset* ds_ = nullptr;
};

}  // namespace

std::string encode_geotiff(const Grid2D& grid, const std::string& layer,
                           const GeoTiffConfig& config) {
  const GridGeometry& g = grid.geometry();
  if (g.cell_count() == 0) throw Error("geotiff: layer '" + layer + "': the grid is empty");
  if (!grid.has_layer(layer)) throw Error("geotiff: no layer '" + layer + "' in the grid");
  register_gtiff();
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GTiff");
  if (!driver) throw Error("geotiff: GDAL has no GTiff driver");
  const std::string path = vsimem_path();
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

Grid2D decode_geotiff(const std::string& bytes, const std::string& layer, const std::string& name,
                      std::string* description) {
  const MemRaster raster(bytes);
  GDALDataset* ds = raster.dataset();
  if (!ds) throw Error(name + ": not a GeoTIFF GDAL can read");
  if (ds->GetRasterCount() != 1)
    throw Error(name + ": " + std::to_string(ds->GetRasterCount()) +
                " bands (expected one: a single layer)");
  double t[6] = {0, 1, 0, 0, 0, -1};
  if (ds->GetGeoTransform(t) != CE_None) throw Error(name + ": no geotransform (not placed)");
  if (t[2] != 0.0 || t[4] != 0.0) throw Error(name + ": a rotated raster is not supported");
  if (!(t[1] > 0.0) || std::abs(t[1] + t[5]) > 1e-9 * t[1])
    throw Error(name + ": pixels are not square and north-up (size " + std::to_string(t[1]) +
                " x " + std::to_string(t[5]) + ")");
  GridGeometry g;
  g.width = ds->GetRasterXSize();
  g.height = ds->GetRasterYSize();
  g.resolution_m = t[1];
  g.origin_m = {t[0], t[3] + t[5] * g.height};
  Grid2D grid(g);
  auto values = grid.add_layer(layer, std::numeric_limits<float>::quiet_NaN());
  GDALRasterBand* band = ds->GetRasterBand(1);
  if (description) *description = band->GetDescription() ? band->GetDescription() : "";
  int has_nodata = 0;
  const double nodata = band->GetNoDataValue(&has_nodata);
  std::vector<float> row(std::size_t(g.width));
  for (int r = 0; r < g.height; ++r) {
    if (band->RasterIO(GF_Read, 0, r, g.width, 1, row.data(), g.width, 1, GDT_Float32, 0, 0) !=
        CE_None)
      throw Error(name + ": row " + std::to_string(r) + " could not be read");
    const int iy = g.height - 1 - r;  // row 0 is the top (largest y)
    for (int ix = 0; ix < g.width; ++ix) {
      const float v = row[std::size_t(ix)];
      const bool missing = !std::isfinite(v) || (has_nodata && std::isfinite(nodata) &&
                                                 double(v) == double(float(nodata)));
      values[g.linear_index(ix, iy)] = missing ? std::numeric_limits<float>::quiet_NaN() : v;
    }
  }
  return grid;
}

Grid2D read_geotiff(const std::filesystem::path& path, const std::string& layer,
                    std::string* description) {
  const std::vector<std::byte> bytes = read_file_bytes(path);
  return decode_geotiff(std::string(reinterpret_cast<const char*>(bytes.data()), bytes.size()),
                        layer, path.string(), description);
}

}  // namespace fieldlidar::io
