#pragma once
// Conversion between pcl::PCLPointCloud2 (the field-wise blob PCL's PCD and PLY readers produce)
// and fieldlidar::PointCloud. Private to io/: PCL never appears in a public header.

#include <cstdint>
#include <string>
#include <vector>

#include <pcl/PCLPointCloud2.h>
#include <pcl/console/print.h>

#include "fieldlidar/core/point_cloud.hpp"

namespace fieldlidar::io::detail {

/// Fields x y z (float32/float64; required), intensity (any numeric type), ring, time offsets or
/// absolute timestamps, label. Time: a field named `t`, `time` or `time_offset` holds offsets from
/// the sweep start (s when floating point, ns when integer, as Ouster's `t`); `timestamp`, or any
/// time field whose values exceed 1000 s, holds absolute times whose unit is found from their
/// magnitude (> 1e17 ns, > 1e14 us, > 1e11 ms, else s): cloud.stamp_s becomes the earliest one
/// and each point's time its offset from it.
/// NaN/Inf coordinates: in an organized cloud (height > 1) they are no-returns and become the
/// all-zero point (Point::is_valid() is false) so rows and columns stay aligned; in an unorganized
/// cloud, or when every point is NaN, they are an error naming `source`.
PointCloud from_pcl_cloud2(const pcl::PCLPointCloud2& blob, const std::string& source);

/// One field of n points: the value of point i is at base + i * stride (a PCLPointField::
/// datatype). Points stored point-major (binary PCD) have stride = point size; field-major
/// planes (decompressed binary_compressed PCD) have stride = field size.
struct FieldView {
  std::string name;
  std::uint8_t datatype = 0;
  const std::uint8_t* base = nullptr;
  std::size_t stride = 0;
};

/// The same conversion as from_pcl_cloud2 from views the caller has bounds-checked.
PointCloud from_field_views(const std::vector<FieldView>& fields, std::uint32_t width,
                            std::uint32_t height, const std::string& source);

/// x y z intensity (float32), ring (uint16) when filled, time (float32 offset, s) or, when
/// stamp_s != 0 and not `time_offsets`, timestamp (float64 absolute, s), label (uint32) when the
/// cloud is labelled.
pcl::PCLPointCloud2 to_pcl_cloud2(const PointCloud& cloud, bool time_offsets = false);

/// The points as text, one line per point, values separated by spaces in field order: float32
/// with 9 significant digits and float64 with 17 (both round-trip exactly), integers in full.
std::string ascii_values(const pcl::PCLPointCloud2& blob);

/// Silences PCL's console messages while a reader or writer runs (the library never prints).
class QuietPcl {
 public:
  QuietPcl() : saved_(pcl::console::getVerbosityLevel()) {
    pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  }
  ~QuietPcl() { pcl::console::setVerbosityLevel(saved_); }
  QuietPcl(const QuietPcl&) = delete;
  QuietPcl& operator=(const QuietPcl&) = delete;

 private:
  pcl::console::VERBOSITY_LEVEL saved_;
};

}  // namespace fieldlidar::io::detail
