// Writing PCD files (ascii, binary, binary_compressed); reading is in pcd.cpp.

#include <cstdio>
#include <sstream>
#include <string>

#include <pcl/io/pcd_io.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/pcd.hpp"
#include "pcl_fields.hpp"

namespace fieldlidar::io {

namespace {

using Field = pcl::PCLPointField;

/// The VIEWPOINT line that stores `origin` (17 significant digits: doubles round-trip).
std::string viewpoint_line(const Eigen::Vector3d& origin) {
  char buf[128];
  std::snprintf(buf, sizeof buf, "VIEWPOINT %.17g %.17g %.17g 1 0 0 0", origin.x(), origin.y(),
                origin.z());
  return buf;
}

std::string header_text(const pcl::PCLPointCloud2& blob, const char* data,
                        const Eigen::Vector3d& origin) {
  std::string fields, sizes, types, counts;
  for (const auto& f : blob.fields) {
    fields.append(" ").append(f.name);
    const bool fp = f.datatype == Field::FLOAT32 || f.datatype == Field::FLOAT64;
    const bool sgn = f.datatype == Field::INT8 || f.datatype == Field::INT16 ||
                     f.datatype == Field::INT32 || f.datatype == Field::INT64;
    const int size = pcl::getFieldSize(f.datatype);
    sizes.append(" ").append(std::to_string(size));
    types += fp ? " F" : sgn ? " I" : " U";
    counts += " 1";
  }
  std::string h = "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS";
  h.append(fields).append("\nSIZE").append(sizes).append("\nTYPE").append(types);
  h.append("\nCOUNT").append(counts).append("\nWIDTH ").append(std::to_string(blob.width));
  h.append("\nHEIGHT ").append(std::to_string(blob.height));
  h.append("\n").append(viewpoint_line(origin)).append("\nPOINTS ");
  h.append(std::to_string(std::size_t(blob.width) * blob.height));
  h.append("\nDATA ").append(data).append("\n");
  return h;
}

}  // namespace

void write_pcd(const std::filesystem::path& path, const PointCloud& cloud,
               const WriteOptions& options) {
  check_writable(path, options.overwrite);
  const pcl::PCLPointCloud2 blob = detail::to_pcl_cloud2(cloud, options.time_offsets);
  std::string out;
  if (!options.binary) {
    out = header_text(blob, "ascii", cloud.origin_m) + detail::ascii_values(blob);
  } else if (!options.compressed || cloud.empty()) {
    out = header_text(blob, "binary", cloud.origin_m);
    out.append(reinterpret_cast<const char*>(blob.data.data()), blob.data.size());
  } else {
    detail::QuietPcl quiet;
    std::ostringstream os;
    pcl::PCDWriter writer;
    if (writer.writeBinaryCompressed(os, blob) != 0)
      throw Error(path.string() + ": PCD binary_compressed encoding failed");
    out = std::move(os).str();
    // PCL writes the VIEWPOINT in float32 with 6 digits: ours keeps origin_m exactly.
    const auto at = out.find("\nVIEWPOINT ");
    const auto eol = at == std::string::npos ? at : out.find('\n', at + 1);
    if (eol == std::string::npos) throw Error(path.string() + ": PCD header without VIEWPOINT");
    out.replace(at + 1, eol - at - 1, viewpoint_line(cloud.origin_m));
  }
  write_file_atomic(path, out.data(), out.size(), options.overwrite);
}

}  // namespace fieldlidar::io
