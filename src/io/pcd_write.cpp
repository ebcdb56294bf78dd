// Writing PCD files (ascii, binary, binary_compressed); reading is in pcd.cpp.

#include <sstream>
#include <string>

#include <pcl/io/pcd_io.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/pcd.hpp"
#include "pcl_fields.hpp"

namespace fieldlidar::io {

namespace {

using Field = pcl::PCLPointField;

std::string header_text(const pcl::PCLPointCloud2& blob, const char* data) {
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
  h.append("\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS ");
  h.append(std::to_string(std::size_t(blob.width) * blob.height));
  h.append("\nDATA ").append(data).append("\n");
  return h;
}

}  // namespace

void write_pcd(const std::filesystem::path& path, const PointCloud& cloud,
               const WriteOptions& options) {
  check_writable(path, options.overwrite);
  const pcl::PCLPointCloud2 blob = detail::to_pcl_cloud2(cloud);
  std::string out;
  if (!options.binary) {
    out = header_text(blob, "ascii") + detail::ascii_values(blob);
  } else if (!options.compressed || cloud.empty()) {
    out = header_text(blob, "binary");
    out.append(reinterpret_cast<const char*>(blob.data.data()), blob.data.size());
  } else {
    detail::QuietPcl quiet;
    std::ostringstream os;
    pcl::PCDWriter writer;
    if (writer.writeBinaryCompressed(os, blob) != 0)
      throw Error(path.string() + ": PCD binary_compressed encoding failed");
    out = std::move(os).str();
  }
  write_file_atomic(path, out.data(), out.size(), options.overwrite);
}

}  // namespace fieldlidar::io
