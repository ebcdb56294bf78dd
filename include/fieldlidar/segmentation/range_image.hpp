#pragma once
/// \file Range image of one sweep (seed 000, step 1): rows = rings, columns = azimuth bins.

#include <cstdint>
#include <span>
#include <vector>

#include "fieldlidar/core/point_cloud.hpp"
#include "fieldlidar/core/sensor_model.hpp"

namespace fieldlidar::segmentation {

/// How a point's row is found.
enum class RowSource {
  kAuto,         ///< ring field when the cloud has one, else estimated rings (see estimate_rings)
  kRingField,    ///< Point::ring (throws fieldlidar::Error when the cloud has no ring field)
  kElevation,    ///< seed 000 formula: row = (atan2(z, hypot(x, y)) + theta_bottom) / res_vertical
  kNearestBeam,  ///< the beam of the sensor table whose elevation is nearest (non-uniform tables)
  kEstimated,    ///< estimate_rings(): scan order, then index rows, then nearest beam
};

struct RangeImageConfig {
  RowSource row_source = RowSource::kAuto;
  int columns = 0;  ///< azimuth bins per revolution; 0 = SensorModel::columns
};

/// Cell labels of the image drawn alongside the range image (seed 000: "an image of labels marks
/// each point's role").
enum class CellLabel : std::uint8_t {
  kEmpty = 0,
  kUnknown = 1,
  kGround = 2,
  kNonGround = 3,
  kCluster = 4,
};

/// A sweep projected onto a rows x cols grid. Per cell the index of the point kept there (the
/// nearest when several fall into one cell, seed 000: duplicates dropped) or -1.
struct RangeImage {
  int rows = 0;
  int cols = 0;
  std::vector<std::int32_t> cell_point;  ///< rows*cols, row-major, -1 = empty
  std::vector<float> cell_range_m;       ///< rows*cols, range of the kept point, 0 = empty
  std::vector<CellLabel> labels;         ///< rows*cols label image
  std::vector<std::int32_t> point_cell;  ///< per input point: its cell (kept or not), -1 = invalid
  std::vector<float> row_altitude_rad;   ///< beam elevation of each row (the sensor's table)
  std::size_t duplicates = 0;            ///< valid points that lost their cell to a nearer one

  std::int32_t at(int row, int col) const { return cell_point[std::size_t(row) * cols + col]; }
  float range_at(int row, int col) const { return cell_range_m[std::size_t(row) * cols + col]; }
  int row_of_cell(std::int32_t cell) const { return cell / cols; }
  int col_of_cell(std::int32_t cell) const { return cell % cols; }

  /// Throws fieldlidar::Error when the cloud cannot be projected (no ring field for kRingField,
  /// ring beyond the sensor's rings, invalid sensor model).
  static RangeImage build(const PointCloud& cloud, const SensorModel& sensor,
                          const RangeImageConfig& config = {});
};

/// Column of azimuth `azimuth_rad` (seed 000: round(atan2(y, x) / theta_horizon) + kscan/2),
/// wrapped into [0, columns).
int azimuth_column(double azimuth_rad, int columns);

/// Rings for a cloud without a ring field (KITTI .bin, unorganised PCD): one per point, 0 =
/// lowest beam, Point::kNoRing for invalid points. Tries, in order: (1) the scan order — a spinning
/// sensor writes ring after ring, so the azimuth wrapping past the ring's start marks a new ring,
/// accepted when it yields exactly sensor.rings() rings; (2) index order — size() a multiple of
/// rings(), the image stored row after row or column after column, accepted when the per-ring
/// median elevation is monotonic (organised Ouster dumps such as RELLIS-3D's); (3) the beam of
/// nearest elevation.
struct RingEstimate {
  std::vector<std::uint16_t> rings;
  enum class Method {
    kRingField,
    kScanOrder,
    kIndexRows,
    kIndexColumns,
    kNearestBeam
  } method = Method::kNearestBeam;
};
RingEstimate estimate_rings(const PointCloud& cloud, const SensorModel& sensor);

}  // namespace fieldlidar::segmentation
