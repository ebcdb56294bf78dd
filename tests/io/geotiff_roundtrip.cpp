// A Grid2D layer written as GeoTIFF bytes and read back by GDAL: size, north-up rows,
// geotransform, no-data NaN, values.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <cpl_vsi.h>
#include <gdal_priv.h>
#include <gtest/gtest.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/geotiff.hpp"

using namespace fieldlidar;

TEST(GeoTiff, LayerRoundTripsThroughGdal) {
  GridGeometry g{.resolution_m = 0.5, .origin_m = {10.0, -4.0}, .width = 4, .height = 3};
  Grid2D grid(g);
  auto v = grid.add_layer("slope_deg", 0.f);
  for (int iy = 0; iy < 3; ++iy)
    for (int ix = 0; ix < 4; ++ix) v[g.linear_index(ix, iy)] = float(10 * iy + ix);
  v[g.linear_index(1, 1)] = std::numeric_limits<float>::quiet_NaN();
  io::GeoTiffConfig config;
  config.origin_offset_m = {1000.0, 2000.0};
  const std::string bytes = io::encode_geotiff(grid, "slope_deg", config);
  ASSERT_GT(bytes.size(), 100u);
  EXPECT_EQ(bytes.substr(0, 4), std::string("II*\0", 4));

  GDALAllRegister();
  const std::string path = "/vsimem/geotiff_roundtrip.tif";
  VSILFILE* f =
      VSIFileFromMemBuffer(path.c_str(), reinterpret_cast<GByte*>(const_cast<char*>(bytes.data())),
                           vsi_l_offset(bytes.size()), FALSE);
  ASSERT_NE(f, nullptr);
  VSIFCloseL(f);
  GDALDataset* ds = static_cast<GDALDataset*>(GDALOpen(path.c_str(), GA_ReadOnly));
  ASSERT_NE(ds, nullptr);
  EXPECT_EQ(ds->GetRasterXSize(), 4);
  EXPECT_EQ(ds->GetRasterYSize(), 3);
  double t[6];
  ASSERT_EQ(ds->GetGeoTransform(t), CE_None);
  EXPECT_DOUBLE_EQ(t[0], 1010.0);
  EXPECT_DOUBLE_EQ(t[1], 0.5);
  EXPECT_DOUBLE_EQ(t[3], 2000.0 - 4.0 + 1.5);  // top edge: largest y
  EXPECT_DOUBLE_EQ(t[5], -0.5);
  GDALRasterBand* band = ds->GetRasterBand(1);
  int has_nodata = 0;
  EXPECT_TRUE(std::isnan(band->GetNoDataValue(&has_nodata)));
  EXPECT_TRUE(has_nodata);
  float row[4];
  ASSERT_EQ(band->RasterIO(GF_Read, 0, 0, 4, 1, row, 4, 1, GDT_Float32, 0, 0), CE_None);
  EXPECT_EQ(row[3], 23.f);  // top row is iy = 2
  ASSERT_EQ(band->RasterIO(GF_Read, 0, 1, 4, 1, row, 4, 1, GDT_Float32, 0, 0), CE_None);
  EXPECT_TRUE(std::isnan(row[1]));
  EXPECT_EQ(row[2], 12.f);
  GDALClose(ds);
  VSIUnlink(path.c_str());

  EXPECT_THROW(io::encode_geotiff(grid, "missing"), Error);
  EXPECT_THROW(io::encode_geotiff(Grid2D(GridGeometry{}), "slope_deg"), Error);
}

namespace {

// A raster made by GDAL itself (bands, geotransform and no-data as given), as bytes.
std::string gdal_raster(int bands, const double (&transform)[6], double nodata) {
  GDALAllRegister();
  const std::string path = "/vsimem/geotiff_made.tif";
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GTiff");
  GDALDataset* ds = driver->Create(path.c_str(), 3, 2, bands, GDT_Float32, nullptr);
  double t[6];
  std::copy(std::begin(transform), std::end(transform), t);
  ds->SetGeoTransform(t);
  float row[3] = {1.f, float(nodata), 3.f};
  for (int b = 1; b <= bands; ++b) {
    ds->GetRasterBand(b)->SetNoDataValue(nodata);
    for (int r = 0; r < 2; ++r)
      if (ds->GetRasterBand(b)->RasterIO(GF_Write, 0, r, 3, 1, row, 3, 1, GDT_Float32, 0, 0) !=
          CE_None)
        ADD_FAILURE() << "GDAL could not write the test raster";
  }
  GDALClose(ds);
  vsi_l_offset size = 0;
  GByte* bytes = VSIGetMemFileBuffer(path.c_str(), &size, FALSE);
  std::string out(reinterpret_cast<const char*>(bytes), size);
  VSIUnlink(path.c_str());
  return out;
}

}  // namespace

// What encode_geotiff writes, decode_geotiff reads back: placement (the origin offset included),
// values, NaN cells.
TEST(GeoTiff, DecodeIsTheInverseOfEncode) {
  GridGeometry g{.resolution_m = 0.5, .origin_m = {10.0, -4.0}, .width = 4, .height = 3};
  Grid2D grid(g);
  auto v = grid.add_layer("traversability", 0.f);
  for (int iy = 0; iy < 3; ++iy)
    for (int ix = 0; ix < 4; ++ix) v[g.linear_index(ix, iy)] = 0.1f * float(4 * iy + ix);
  v[g.linear_index(2, 0)] = std::numeric_limits<float>::quiet_NaN();
  io::GeoTiffConfig config;
  config.origin_offset_m = {1000.0, 2000.0};
  const Grid2D back = io::decode_geotiff(io::encode_geotiff(grid, "traversability", config), "tau");
  const GridGeometry& b = back.geometry();
  EXPECT_EQ(b.width, 4);
  EXPECT_EQ(b.height, 3);
  EXPECT_DOUBLE_EQ(b.resolution_m, 0.5);
  EXPECT_DOUBLE_EQ(b.origin_m.x(), 1010.0);
  EXPECT_DOUBLE_EQ(b.origin_m.y(), 1996.0);
  ASSERT_TRUE(back.has_layer("tau"));
  for (int iy = 0; iy < 3; ++iy)
    for (int ix = 0; ix < 4; ++ix) {
      const float want = v[g.linear_index(ix, iy)], got = back.layer("tau")[b.linear_index(ix, iy)];
      if (std::isnan(want))
        EXPECT_TRUE(std::isnan(got)) << ix << "," << iy;
      else
        EXPECT_EQ(got, want) << ix << "," << iy;
    }
}

// A raster with a numeric no-data value reads it as NaN; bytes that are no raster, two bands, a
// rotated or a non-square raster are errors naming the source.
TEST(GeoTiff, DecodeRefusesWhatItCannotPlace) {
  const Grid2D ok = io::decode_geotiff(gdal_raster(1, {5, 0.25, 0, 9, 0, -0.25}, -9999), "x");
  EXPECT_EQ(ok.geometry().width, 3);
  EXPECT_DOUBLE_EQ(ok.geometry().origin_m.y(), 8.5);
  EXPECT_EQ(ok.layer("x")[ok.geometry().linear_index(0, 0)], 1.f);
  EXPECT_TRUE(std::isnan(ok.layer("x")[ok.geometry().linear_index(1, 0)]));
  const auto message = [](const std::string& bytes) {
    try {
      io::decode_geotiff(bytes, "x", "map.tif");
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("P5\n3 2\n255\nabcdef").find("map.tif: not a GeoTIFF"), std::string::npos);
  EXPECT_NE(message(gdal_raster(2, {5, 0.25, 0, 9, 0, -0.25}, 0)).find("2 bands"),
            std::string::npos);
  EXPECT_NE(message(gdal_raster(1, {5, 0.25, 0.1, 9, 0, -0.25}, 0)).find("rotated"),
            std::string::npos);
  EXPECT_NE(message(gdal_raster(1, {5, 0.25, 0, 9, 0, -0.5}, 0)).find("not square"),
            std::string::npos);
  EXPECT_THROW(io::read_geotiff("/nonexistent/map.tif", "x"), Error);
}
