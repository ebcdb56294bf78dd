#include "pcd_header.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <string_view>

#include <pcl/PCLPointField.h>

#include "fieldlidar/core/error.hpp"
#include "text_tokens.hpp"

namespace fieldlidar::io::detail {

namespace {

using Field = pcl::PCLPointField;

// Bounds that no real scan reaches; they keep a corrupt header from asking for absurd memory.
constexpr std::size_t kMaxHeaderBytes = 1 << 16;
constexpr std::uint64_t kMaxPointStep = 1 << 16;

std::uint64_t to_uint(std::string_view s, const std::string& source, std::string_view what) {
  std::uint64_t v = 0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || ptr != s.data() + s.size())
    pcd_fail(source, "header: " + std::string(what) + " value '" + std::string(s) +
                         "' is not a non-negative integer");
  return v;
}

/// A whole token as a finite double.
bool to_double(std::string_view s, double& v) {
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  return ec == std::errc() && ptr == s.data() + s.size() && std::isfinite(v);
}

}  // namespace

void pcd_fail(const std::string& source, const std::string& what) {
  throw Error(source + ": PCD " + what);
}

Eigen::Vector3d pcd_origin(const PcdHeader& h) {
  const auto& v = h.viewpoint;
  const bool identity =
      std::abs(std::abs(v[3]) - 1.0) < 1e-9 && v[4] == 0 && v[5] == 0 && v[6] == 0;
  return identity ? Eigen::Vector3d(v[0], v[1], v[2]) : Eigen::Vector3d::Zero();
}

std::uint8_t pcd_pcl_type(char type, unsigned size) {
  switch (type) {
    case 'F':
      return size == 4 ? Field::FLOAT32 : size == 8 ? Field::FLOAT64 : 0;
    case 'I':
      return size == 1   ? Field::INT8
             : size == 2 ? Field::INT16
             : size == 4 ? Field::INT32
             : size == 8 ? Field::INT64
                         : 0;
    case 'U':
      return size == 1   ? Field::UINT8
             : size == 2 ? Field::UINT16
             : size == 4 ? Field::UINT32
             : size == 8 ? Field::UINT64
                         : 0;
    default:
      return 0;
  }
}

PcdHeader parse_pcd_header(std::span<const std::byte> bytes, const std::string& source) {
  const std::string_view text(reinterpret_cast<const char*>(bytes.data()),
                              std::min(bytes.size(), kMaxHeaderBytes));
  if (bytes.empty()) pcd_fail(source, "file is empty");
  PcdHeader h;
  std::size_t pos = 0;
  bool seen_fields = false;
  while (h.data_type < 0) {
    if (pos >= text.size())
      pcd_fail(source, "header has no DATA line (truncated, or not a PCD file)");
    const auto eol = text.find('\n', pos);
    if (eol == std::string_view::npos)
      pcd_fail(source, "header has no DATA line (truncated, or not a PCD file)");
    const auto line = text.substr(pos, eol - pos);
    pos = eol + 1;
    const auto tok = detail::split_tokens(line);
    if (tok.empty() || tok[0][0] == '#') continue;
    const std::string_view key = tok[0];
    const std::size_t nvals = tok.size() - 1;
    auto need_fields = [&] {
      if (!seen_fields) pcd_fail(source, "header: " + std::string(key) + " before FIELDS");
      if (nvals != h.names.size())
        pcd_fail(source, "header: " + std::string(key) + " has " + std::to_string(nvals) +
                             " entries for " + std::to_string(h.names.size()) + " fields");
    };
    if (key == "VERSION") {
      continue;
    } else if (key == "FIELDS" || key == "COLUMNS") {
      if (nvals == 0) pcd_fail(source, "header: FIELDS is empty");
      seen_fields = true;
      h.names.assign(tok.begin() + 1, tok.end());
      h.sizes.assign(nvals, 4);
      h.types.assign(nvals, 'F');
      h.counts.assign(nvals, 1);
    } else if (key == "SIZE") {
      need_fields();
      for (std::size_t i = 0; i < nvals; ++i) {
        const auto size = to_uint(tok[i + 1], source, key);
        if (size != 1 && size != 2 && size != 4 && size != 8)
          pcd_fail(source, "header: field '" + h.names[i] + "' has SIZE " + std::to_string(size) +
                               " (1, 2, 4 or 8 bytes)");
        h.sizes[i] = static_cast<unsigned>(size);
      }
    } else if (key == "TYPE") {
      need_fields();
      for (std::size_t i = 0; i < nvals; ++i) {
        if (tok[i + 1].size() != 1)
          pcd_fail(source, "header: TYPE '" + std::string(tok[i + 1]) + "'");
        h.types[i] = tok[i + 1][0];
      }
    } else if (key == "COUNT") {
      need_fields();
      for (std::size_t i = 0; i < nvals; ++i) {
        const auto c = to_uint(tok[i + 1], source, key);
        if (c < 1 || c > kMaxPointStep)
          pcd_fail(source, "header: COUNT " + std::to_string(c) + " of field '" + h.names[i] + "'");
        h.counts[i] = static_cast<unsigned>(c);
      }
    } else if (key == "WIDTH" && nvals == 1) {
      h.width = to_uint(tok[1], source, key);
      h.has_width = true;
    } else if (key == "HEIGHT" && nvals == 1) {
      h.height = to_uint(tok[1], source, key);
      h.has_height = true;
    } else if (key == "POINTS" && nvals == 1) {
      h.points = to_uint(tok[1], source, key);
      h.has_points = true;
    } else if (key == "VIEWPOINT") {
      // Only the pose itself is used (origin_of); a malformed one is ignored, as PCL does.
      std::array<double, 7> v{};
      bool ok = nvals == 7;
      for (std::size_t i = 0; ok && i < 7; ++i) ok = to_double(tok[i + 1], v[i]);
      if (ok) h.viewpoint = v;
    } else if (key == "DATA" && nvals == 1) {
      if (tok[1] == "ascii")
        h.data_type = 0;
      else if (tok[1] == "binary")
        h.data_type = 1;
      else if (tok[1] == "binary_compressed")
        h.data_type = 2;
      else
        pcd_fail(source, "header: DATA '" + std::string(tok[1]) +
                             "' is not ascii, binary or binary_compressed");
      h.data_offset = pos;
    } else {
      pcd_fail(source, "header: unexpected line '" +
                           std::string(line.substr(0, std::min<std::size_t>(line.size(), 40))) +
                           "' (not a PCD file?)");
    }
  }
  if (!seen_fields) pcd_fail(source, "header has no FIELDS line");
  for (std::size_t i = 0; i < h.names.size(); ++i) {
    if (pcd_pcl_type(h.types[i], h.sizes[i]) == 0)
      pcd_fail(source, "header: field '" + h.names[i] + "' has TYPE " + h.types[i] + " with SIZE " +
                           std::to_string(h.sizes[i]));
    h.point_step += std::uint64_t(h.sizes[i]) * h.counts[i];
  }
  if (h.point_step > kMaxPointStep) pcd_fail(source, "header: point size is absurdly large");
  if (!h.has_height) h.height = 1;
  if (!h.has_width) h.width = h.height ? h.points / h.height : 0;
  if (!h.has_points) h.points = h.width * h.height;
  if (h.width > UINT32_MAX || h.height > UINT32_MAX || h.width * h.height != h.points)
    pcd_fail(source, "header: WIDTH " + std::to_string(h.width) + " x HEIGHT " +
                         std::to_string(h.height) + " != POINTS " + std::to_string(h.points));
  return h;
}

}  // namespace fieldlidar::io::detail
