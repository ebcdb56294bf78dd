#include "fieldlidar/io/ply.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <optional>
#include <string_view>
#include <vector>

#include <pcl/io/ply_io.h>

#include "fieldlidar/core/error.hpp"
#include "pcl_fields.hpp"
#include "text_tokens.hpp"

namespace fieldlidar::io {

namespace {
/// Header comment holding PointCloud::origin_m: `comment fieldlidar origin_m X Y Z` (m).
constexpr const char* kOriginComment[2] = {"fieldlidar", "origin_m"};

constexpr std::size_t kMaxHeaderBytes = 1 << 16;

[[noreturn]] void ply_fail(const std::string& source, const std::string& what) {
  throw Error(source + ": PLY " + what);
}

std::size_t scalar_size(std::string_view t) {
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
  if (t == "int" || t == "uint" || t == "int32" || t == "uint32" || t == "float" || t == "float32")
    return 4;
  if (t == "double" || t == "float64") return 8;
  return 0;
}

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::uint64_t min_bytes = 0;  ///< per item; a list counts only its length field
  std::vector<std::string> properties;
  bool has_list = false;
};

/// The origin of a `comment fieldlidar origin_m X Y Z` line, if `tok` is one.
std::optional<Eigen::Vector3d> origin_comment(const std::vector<std::string_view>& tok) {
  if (tok.size() != 6 || tok[1] != kOriginComment[0] || tok[2] != kOriginComment[1])
    return std::nullopt;
  Eigen::Vector3d o;
  for (int i = 0; i < 3; ++i) {
    const auto s = tok[std::size_t(i) + 3];
    const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), o[i]);
    if (ec != std::errc() || p != s.data() + s.size() || !std::isfinite(o[i])) return std::nullopt;
  }
  return o;
}

/// Checks the header strictly and bounds every element count by the bytes that follow it, so
/// that PCL's parser never sees a count it would allocate for but cannot read.
/// Returns the cloud's origin_m (from the fieldlidar origin comment; zero without one).
Eigen::Vector3d check_header(std::string_view text, std::uint64_t file_size,
                             const std::string& source) {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  if (file_size == 0) ply_fail(source, "file is empty");
  if (text.substr(0, 4) != "ply\n" && text.substr(0, 5) != "ply\r\n")
    ply_fail(source, "file does not start with 'ply' (not a PLY file)");
  std::size_t pos = text.find('\n') + 1;
  int format = -1;  // 0 ascii, 1 binary
  std::vector<PlyElement> elements;
  std::optional<std::uint64_t> num_cols, num_rows;  // obj_info organized size
  bool ended = false;
  while (!ended) {
    const auto eol = text.find('\n', pos);
    if (eol == std::string_view::npos) ply_fail(source, "header has no end_header (truncated?)");
    std::string_view line = text.substr(pos, eol - pos);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    const auto tok = detail::split_tokens(line);
    pos = eol + 1;
    if (tok.empty()) continue;
    // PCL's header parser splits lines differently from ours and asserts on what it does not
    // expect, so only lines of single-space separated words are passed on to it.
    std::size_t words = 0;
    for (const auto& t : tok) words += t.size();
    if (line.front() == ' ' || line.front() == '\t' ||
        (tok[0] != "comment" && line.size() != words + tok.size() - 1))
      ply_fail(source, "header line '" + std::string(line.substr(0, 60)) +
                           "' is not words separated by single spaces");
    const auto key = tok[0];
    if (key == "comment") {
      if (const auto o = origin_comment(tok)) origin = *o;
      continue;
    }
    if (key == "obj_info") {
      // PCL takes num_cols x num_rows as the organized size of the vertex list and aborts when
      // the vertex count does not fit it, so both must be whole numbers matching that count.
      if (tok.size() >= 3 && (tok[1] == "num_cols" || tok[1] == "num_rows")) {
        std::uint64_t v = 0;
        const auto [p, ec] = std::from_chars(tok[2].data(), tok[2].data() + tok[2].size(), v);
        if (ec != std::errc() || p != tok[2].data() + tok[2].size() || tok.size() != 3)
          ply_fail(source, "obj_info " + std::string(tok[1]) + " is not a whole number");
        (tok[1] == "num_cols" ? num_cols : num_rows) = v;
      }
      continue;
    }
    if (key == "format" && tok.size() == 3 && format < 0) {
      if (tok[2] != "1.0") ply_fail(source, "version '" + std::string(tok[2]) + "' is not 1.0");
      if (tok[1] == "ascii")
        format = 0;
      else if (tok[1] == "binary_little_endian" || tok[1] == "binary_big_endian")
        format = 1;
      else
        ply_fail(source, "format '" + std::string(tok[1]) + "' is unknown");
    } else if (key == "element" && tok.size() == 3) {
      PlyElement e;
      e.name = tok[1];
      const auto [p, ec] = std::from_chars(tok[2].data(), tok[2].data() + tok[2].size(), e.count);
      if (ec != std::errc() || p != tok[2].data() + tok[2].size())
        ply_fail(source,
                 "element '" + e.name + "' count '" + std::string(tok[2]) + "' is not a number");
      elements.push_back(e);
    } else if (key == "property" && !elements.empty()) {
      auto& e = elements.back();
      if (tok.size() == 3 && scalar_size(tok[1]) > 0) {
        e.min_bytes += scalar_size(tok[1]);
        e.properties.emplace_back(tok[2]);
      } else if (tok.size() == 5 && tok[1] == "list" && scalar_size(tok[2]) > 0 &&
                 scalar_size(tok[3]) > 0) {
        e.min_bytes += scalar_size(tok[2]);
        e.properties.emplace_back(tok[4]);
        e.has_list = true;
      } else {
        ply_fail(source, "property line of element '" + e.name + "' is malformed");
      }
    } else if (key == "end_header" && tok.size() == 1) {
      ended = true;
    } else {
      ply_fail(source, "unexpected header line starting '" + std::string(key) + "'");
    }
  }
  if (format < 0) ply_fail(source, "header has no format line");
  const std::uint64_t available = file_size - pos;
  std::uint64_t need = 0;
  bool vertex = false;
  for (const auto& e : elements) {
    if (e.properties.empty() && e.count > 0)
      ply_fail(source, "element '" + e.name + "' has no properties");
    // ascii: every value takes at least one character and a separator.
    const std::uint64_t item = format == 0 ? 2 * e.properties.size() : e.min_bytes;
    if (e.count > (available - std::min(need, available)) / std::max<std::uint64_t>(item, 1))
      ply_fail(source, "truncated: element '" + e.name + "' has " + std::to_string(e.count) +
                           " items but only " + std::to_string(available) +
                           " bytes follow the header");
    need += e.count * item;
    if (e.name == "vertex") {
      vertex = true;
      if ((num_cols || num_rows) &&
          (!num_cols || !num_rows || *num_rows == 0 || *num_cols > e.count / *num_rows ||
           *num_cols * *num_rows != e.count))
        ply_fail(source, "obj_info num_cols x num_rows does not match the " +
                             std::to_string(e.count) + " vertices");
      if (e.has_list) ply_fail(source, "vertex element has a list property (meshes are not read)");
      for (const char* axis : {"x", "y", "z"})
        if (std::find(e.properties.begin(), e.properties.end(), axis) == e.properties.end())
          ply_fail(source, std::string("vertex element has no '") + axis + "' property");
    }
  }
  if (!vertex) ply_fail(source, "has no vertex element");
  return origin;
}

/// The first kMaxHeaderBytes of the file (the header must lie within them) and its size.
std::string read_head(const std::filesystem::path& path, std::uint64_t& file_size) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw Error(path.string() + ": no such file");
  file_size = std::filesystem::file_size(path, ec);
  if (ec) throw Error(path.string() + ": cannot determine its size");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path.string() + ": cannot open for reading");
  std::string head(std::min<std::uint64_t>(file_size, kMaxHeaderBytes), '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  if (!in) throw Error(path.string() + ": read failed");
  return head;
}

}  // namespace

PointCloud read_ply(const std::filesystem::path& path) {
  std::uint64_t file_size = 0;
  const std::string head = read_head(path, file_size);
  const Eigen::Vector3d origin = check_header(head, file_size, path.string());
  pcl::PCLPointCloud2 blob;
  {
    detail::QuietPcl quiet;
    pcl::PLYReader reader;
    Eigen::Vector4f origin;
    Eigen::Quaternionf orientation;
    int version = 0;
    int rc = -1;
    try {
      rc = reader.read(path.string(), blob, origin, orientation, version);
    } catch (const std::exception& e) {
      ply_fail(path.string(), std::string("could not be parsed: ") + e.what());
    }
    if (rc < 0) ply_fail(path.string(), "could not be parsed (malformed or truncated body)");
  }
  PointCloud cloud = detail::from_pcl_cloud2(blob, path.string());
  cloud.origin_m = origin;
  return cloud;
}

namespace {

const char* ply_type(std::uint8_t datatype) {
  using Field = pcl::PCLPointField;
  switch (datatype) {
    case Field::INT8:
      return "char";
    case Field::UINT8:
      return "uchar";
    case Field::INT16:
      return "short";
    case Field::UINT16:
      return "ushort";
    case Field::INT32:
      return "int";
    case Field::UINT32:
      return "uint";
    case Field::FLOAT32:
      return "float";
    case Field::FLOAT64:
      return "double";
    default:
      return nullptr;
  }
}

}  // namespace

std::string encode_ply(const PointCloud& cloud, bool binary, bool time_offsets) {
  const pcl::PCLPointCloud2 blob = detail::to_pcl_cloud2(cloud, time_offsets);
  const std::size_t n = std::size_t(blob.width) * blob.height;
  std::string out = "ply\nformat ";
  out += binary ? "binary_little_endian 1.0\n" : "ascii 1.0\n";
  out += "comment fieldlidar\n";
  // A georeferenced cloud's origin_m, exactly (17 digits), in a header comment.
  if (!cloud.origin_m.isZero()) {
    char line[160];
    std::snprintf(line, sizeof line, "comment %s %s %.17g %.17g %.17g\n", kOriginComment[0],
                  kOriginComment[1], cloud.origin_m.x(), cloud.origin_m.y(), cloud.origin_m.z());
    out += line;
  }
  if (blob.height > 1)  // organized: rows x columns, as PCL writes it
    out += "obj_info num_cols " + std::to_string(blob.width) + "\nobj_info num_rows " +
           std::to_string(blob.height) + "\n";
  out += "element vertex " + std::to_string(n) + "\n";
  std::size_t item = 0;
  for (const auto& f : blob.fields) {
    const char* type = ply_type(f.datatype);
    if (!type) throw Error("PLY: field '" + f.name + "' has no PLY type");
    out += std::string("property ") + type + " " + f.name + "\n";
    item += pcl::getFieldSize(f.datatype);
  }
  out += "end_header\n";
  if (!binary) return out + detail::ascii_values(blob);
  out.reserve(out.size() + n * item);
  for (std::size_t i = 0; i < n; ++i) {
    const auto* p = reinterpret_cast<const char*>(blob.data.data() + i * blob.point_step);
    for (const auto& f : blob.fields) out.append(p + f.offset, pcl::getFieldSize(f.datatype));
  }
  return out;
}

void write_ply(const std::filesystem::path& path, const PointCloud& cloud,
               const WriteOptions& options) {
  check_writable(path, options.overwrite);
  const std::string bytes = encode_ply(cloud, options.binary, options.time_offsets);
  write_file_atomic(path, bytes, options.overwrite);
}

}  // namespace fieldlidar::io
