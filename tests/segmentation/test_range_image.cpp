// Range image (seed 000, step 1) and ring estimation.

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/segmentation/range_image.hpp"
#include "seg_test_util.hpp"
#include "test_data.hpp"

namespace fieldlidar::segmentation {
namespace {

using test::Box;
using test::synthetic_scan;

auto flat(double h) {
  return [h](double, double) { return -h; };
}

TEST(RangeImage, SeedFormulaPlacesAPointByElevationAndAzimuth) {
  const SensorModel vlp = SensorModel::vlp16();
  PointCloud cloud;
  // Elevation -15 deg (row 0), azimuth 0 (column kscan/2).
  const double el = -15.0 * std::numbers::pi / 180.0;
  Point p;
  p.x = float(10 * std::cos(el));
  p.z = float(10 * std::sin(el));
  cloud.push_back(p);
  // Elevation +1 deg (row 8), azimuth +90 deg: column 1800/2 + 450.
  const double el2 = 1.0 * std::numbers::pi / 180.0;
  Point q;
  q.y = float(5 * std::cos(el2));
  q.z = float(5 * std::sin(el2));
  cloud.push_back(q);
  RangeImageConfig cfg;
  cfg.row_source = RowSource::kElevation;
  const RangeImage img = RangeImage::build(cloud, vlp, cfg);
  EXPECT_EQ(img.rows, 16);
  EXPECT_EQ(img.cols, 1800);
  EXPECT_EQ(img.at(0, 900), 0);
  EXPECT_EQ(img.at(8, 1350), 1);
  EXPECT_NEAR(img.range_at(8, 1350), 5.0, 1e-5);
  EXPECT_EQ(azimuth_column(-std::numbers::pi, 1800), 0);
  EXPECT_EQ(azimuth_column(std::numbers::pi - 1e-9, 1800), 0);  // wraps
}

TEST(RangeImage, DuplicateCellKeepsTheNearerReturn) {
  const SensorModel vlp = SensorModel::vlp16();
  PointCloud cloud;
  cloud.fields.ring = true;
  Point far;
  far.x = 20.f;
  far.ring = 7;
  Point near = far;
  near.x = 8.f;
  cloud.push_back(far);
  cloud.push_back(near);
  const RangeImage img = RangeImage::build(cloud, vlp);
  const int col = azimuth_column(0.0, img.cols);
  EXPECT_EQ(img.at(7, col), 1);
  EXPECT_EQ(img.duplicates, 1u);
  EXPECT_EQ(img.point_cell[0], img.point_cell[1]);  // the loser still knows its cell
  EXPECT_EQ(img.labels[std::size_t(7) * img.cols + col], CellLabel::kUnknown);
}

TEST(RangeImage, RingFieldBeyondTheSensorIsAnError) {
  PointCloud cloud;
  cloud.fields.ring = true;
  Point p;
  p.x = 5.f;
  p.ring = 40;
  cloud.push_back(p);
  EXPECT_THROW(RangeImage::build(cloud, SensorModel::vlp16()), Error);
  PointCloud no_ring;
  no_ring.push_back(p);
  RangeImageConfig cfg;
  cfg.row_source = RowSource::kRingField;
  EXPECT_THROW(RangeImage::build(no_ring, SensorModel::vlp16(), cfg), Error);
}

TEST(RangeImage, NearestBeamMatchesTheRingsOfANonUniformTable) {
  // HDL-64E has two blocks with different spacing: the uniform seed formula is off by several
  // rows at the bottom, the nearest-beam rule is exact on a noise-free scan.
  const SensorModel hdl = SensorModel::hdl64e();
  const PointCloud cloud = synthetic_scan(hdl, flat(1.73), {{{4, -1, -1.73}, {6, 1, 0.5}}});
  RangeImageConfig nearest;
  nearest.row_source = RowSource::kNearestBeam;
  const RangeImage img = RangeImage::build(cloud, hdl, nearest);
  std::size_t wrong = 0;
  for (std::size_t i = 0; i < cloud.size(); ++i)
    if (img.row_of_cell(img.point_cell[i]) != cloud.points[i].ring) ++wrong;
  EXPECT_EQ(wrong, 0u);
  RangeImageConfig uniform;
  uniform.row_source = RowSource::kElevation;
  const RangeImage u = RangeImage::build(cloud, hdl, uniform);
  std::size_t off = 0;
  for (std::size_t i = 0; i < cloud.size(); ++i)
    if (u.point_cell[i] >= 0 && u.row_of_cell(u.point_cell[i]) != cloud.points[i].ring) ++off;
  EXPECT_GT(off, cloud.size() / 4);
}

TEST(RingEstimate, ScanOrderRecoversTheRingsOfAnUnorganisedSweep) {
  const SensorModel vlp = SensorModel::vlp16();
  // A yard walled in on all sides so that every ring has returns.
  PointCloud cloud = synthetic_scan(vlp, flat(0.8),
                                    {{{3, -2, -0.8}, {4, 2, 1.5}},
                                     {{25, -30, -0.8}, {26, 30, 20}},
                                     {{-26, -30, -0.8}, {-25, 30, 20}},
                                     {{-30, 25, -0.8}, {30, 26, 20}},
                                     {{-30, -26, -0.8}, {30, -25, 20}}});
  const std::vector<std::uint16_t> truth = [&] {
    std::vector<std::uint16_t> r;
    for (const auto& p : cloud.points) r.push_back(p.ring);
    return r;
  }();
  for (auto& p : cloud.points) p.ring = Point::kNoRing;
  cloud.fields.ring = false;
  const RingEstimate est = estimate_rings(cloud, vlp);
  EXPECT_EQ(est.method, RingEstimate::Method::kScanOrder);
  EXPECT_EQ(est.rings, truth);
}

TEST(RingEstimate, KittiFramesHave64MonotonicRings) {
  FIELDLIDAR_REQUIRE_DATA("kitti00/000000.bin");
  const PointCloud cloud = test::read_bin(fieldlidar::test::data_file("kitti00/000000.bin"));
  const RingEstimate est = estimate_rings(cloud, SensorModel::hdl64e());
  ASSERT_EQ(est.method, RingEstimate::Method::kScanOrder);
  std::vector<double> sum(64, 0);
  std::vector<std::size_t> n(64, 0);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    ASSERT_LT(est.rings[i], 64);
    const auto& p = cloud.points[i];
    sum[est.rings[i]] += std::atan2(p.z, std::hypot(p.x, p.y));
    ++n[est.rings[i]];
  }
  for (int r = 0; r < 64; ++r) ASSERT_GT(n[r], 900u) << "ring " << r;
  for (int r = 1; r < 64; ++r) EXPECT_GT(sum[r] / n[r], sum[r - 1] / n[r - 1]) << "ring " << r;
}

TEST(RingEstimate, RellisColumnMajorDumpIsRecognised) {
  FIELDLIDAR_REQUIRE_DATA("rellis3d/000001.bin");
  const PointCloud cloud = test::read_bin(fieldlidar::test::data_file("rellis3d/000001.bin"));
  const RingEstimate est = estimate_rings(cloud, SensorModel::os1_64());
  EXPECT_EQ(est.method, RingEstimate::Method::kIndexColumns);
  // Index 63 of each column is the lowest beam of that firing.
  for (std::size_t i = 63; i < cloud.size(); i += 64)
    if (cloud.points[i].is_valid()) {
      EXPECT_EQ(est.rings[i], 0);
      break;
    }
  RangeImageConfig cfg;
  cfg.columns = 2048;  // RELLIS-3D recorded the OS1-64 in 2048 x 10 Hz mode
  const RangeImage img = RangeImage::build(cloud, SensorModel::os1_64(), cfg);
  EXPECT_EQ(img.rows, 64);
  EXPECT_LT(img.duplicates, cloud.valid_count() / 5);
}

}  // namespace
}  // namespace fieldlidar::segmentation
