// A Grid2D layer written as GeoTIFF bytes and read back by GDAL: size, north-up rows,
// geotransform, no-data NaN, values.
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
