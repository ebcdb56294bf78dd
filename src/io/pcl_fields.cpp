#include "pcl_fields.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <optional>
#include <vector>

#include "fieldlidar/core/error.hpp"

namespace fieldlidar::io::detail {

namespace {

using Field = pcl::PCLPointField;

/// Calls store(i, value) for every point with the field's value converted from its stored type.
/// One pass per field with the type fixed outside the loop keeps this a strided copy.
template <typename T, typename Store>
void extract(const std::uint8_t* data, std::size_t n, std::size_t step, std::size_t offset,
             Store&& store) {
  if (n == 0) return;  // data may be null for an empty cloud
  const std::uint8_t* p = data + offset;
  for (std::size_t i = 0; i < n; ++i, p += step) {
    T v;
    std::memcpy(&v, p, sizeof(T));
    store(i, v);
  }
}

template <typename Store>
bool visit(const FieldView& f, std::size_t n, Store&& store) {
  const auto* d = f.base;
  const std::size_t s = f.stride;
  constexpr std::size_t o = 0;
  switch (f.datatype) {
    case Field::INT8:
      extract<std::int8_t>(d, n, s, o, store);
      return true;
    case Field::UINT8:
      extract<std::uint8_t>(d, n, s, o, store);
      return true;
    case Field::INT16:
      extract<std::int16_t>(d, n, s, o, store);
      return true;
    case Field::UINT16:
      extract<std::uint16_t>(d, n, s, o, store);
      return true;
    case Field::INT32:
      extract<std::int32_t>(d, n, s, o, store);
      return true;
    case Field::UINT32:
      extract<std::uint32_t>(d, n, s, o, store);
      return true;
    case Field::INT64:
      extract<std::int64_t>(d, n, s, o, store);
      return true;
    case Field::UINT64:
      extract<std::uint64_t>(d, n, s, o, store);
      return true;
    case Field::FLOAT32:
      extract<float>(d, n, s, o, store);
      return true;
    case Field::FLOAT64:
      extract<double>(d, n, s, o, store);
      return true;
    default:
      return false;
  }
}

std::size_t type_size(std::uint8_t datatype) {
  switch (datatype) {
    case Field::INT8:
    case Field::UINT8:
    case Field::BOOL:
      return 1;
    case Field::INT16:
    case Field::UINT16:
      return 2;
    case Field::INT32:
    case Field::UINT32:
    case Field::FLOAT32:
      return 4;
    case Field::INT64:
    case Field::UINT64:
    case Field::FLOAT64:
      return 8;
    default:
      return 0;
  }
}

bool is_integer(std::uint8_t datatype) {
  return datatype != Field::FLOAT32 && datatype != Field::FLOAT64;
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (s.rfind("scalar_", 0) == 0) s.erase(0, 7);  // CloudCompare's PLY property prefix
  return s;
}

const FieldView* find(const std::vector<FieldView>& fields,
                      std::initializer_list<const char*> names) {
  for (const char* name : names)
    for (const auto& f : fields)
      if (lower(f.name) == name) return &f;
  return nullptr;
}

/// Seconds per unit of an absolute time whose largest value is `max_abs` (epoch-based clocks).
double absolute_time_unit_s(double max_abs) {
  if (max_abs > 1e17) return 1e-9;
  if (max_abs > 1e14) return 1e-6;
  if (max_abs > 1e11) return 1e-3;
  return 1.0;
}

}  // namespace

PointCloud from_pcl_cloud2(const pcl::PCLPointCloud2& blob, const std::string& source) {
  const std::size_t n = std::size_t(blob.width) * blob.height;
  if (blob.data.size() < n * blob.point_step)
    throw Error(source + ": point data holds " + std::to_string(blob.data.size()) +
                " bytes, expected " + std::to_string(n * blob.point_step));
  std::vector<FieldView> views;
  for (const auto& f : blob.fields) {
    const std::size_t size = type_size(f.datatype);
    if (size == 0 || f.offset + size * std::max<std::uint32_t>(f.count, 1) > blob.point_step)
      throw Error(source + ": field '" + f.name + "' has an unsupported type or lies outside the " +
                  std::to_string(blob.point_step) + "-byte point");
    // An empty cloud has no data buffer to point into.
    const std::uint8_t* base = blob.data.empty() ? nullptr : blob.data.data() + f.offset;
    views.push_back({f.name, f.datatype, base, blob.point_step});
  }
  return from_field_views(views, blob.width, blob.height, source);
}

PointCloud from_field_views(const std::vector<FieldView>& blob_fields, std::uint32_t width,
                            std::uint32_t height, const std::string& source) {
  const std::size_t n = std::size_t(width) * height;
  for (const auto& f : blob_fields)
    if (type_size(f.datatype) == 0)
      throw Error(source + ": field '" + f.name + "' has an unsupported type");
  const FieldView* fx = find(blob_fields, {"x"});
  const FieldView* fy = find(blob_fields, {"y"});
  const FieldView* fz = find(blob_fields, {"z"});
  if (!fx || !fy || !fz) throw Error(source + ": has no x, y and z fields");
  for (const FieldView* f : {fx, fy, fz})
    if (f->datatype != Field::FLOAT32 && f->datatype != Field::FLOAT64)
      throw Error(source + ": coordinate field '" + f->name + "' is not float32 or float64");

  PointCloud cloud;
  cloud.points.resize(n);
  cloud.width = width;
  cloud.height = height;
  auto& pts = cloud.points;
  visit(*fx, n, [&](std::size_t i, auto v) { pts[i].x = static_cast<float>(v); });
  visit(*fy, n, [&](std::size_t i, auto v) { pts[i].y = static_cast<float>(v); });
  visit(*fz, n, [&](std::size_t i, auto v) { pts[i].z = static_cast<float>(v); });

  if (const FieldView* f = find(blob_fields, {"intensity", "i"})) {
    cloud.fields.intensity = true;
    visit(*f, n, [&](std::size_t i, auto v) {
      const float x = static_cast<float>(v);
      pts[i].intensity = std::isfinite(x) ? x : 0.f;
    });
  }
  if (const FieldView* f = find(blob_fields, {"ring", "channel", "laser_id"})) {
    cloud.fields.ring = true;
    visit(*f, n, [&](std::size_t i, auto v) {
      const double r = static_cast<double>(v);
      pts[i].ring = (r >= 0 && r < Point::kNoRing) ? static_cast<std::uint16_t>(r) : Point::kNoRing;
    });
  }
  if (const FieldView* f = find(blob_fields, {"label"})) {
    cloud.fields.label = true;
    cloud.labels.resize(n);
    visit(*f, n, [&](std::size_t i, auto v) {
      const double l = static_cast<double>(v);
      cloud.labels[i] = (l >= 0 && l <= UINT32_MAX) ? static_cast<std::uint32_t>(l) : 0u;
    });
  }
  const FieldView* ft = find(blob_fields, {"timestamp"});
  const bool named_absolute = ft != nullptr;
  if (!ft) ft = find(blob_fields, {"t", "time", "time_offset"});
  if (ft && n > 0) {
    // Two passes over the field (range, then offsets) rather than a temporary copy.
    double max_abs = 0.0;
    double min_nonzero = std::numeric_limits<double>::infinity();
    visit(*ft, n, [&](std::size_t, auto raw) {
      const double v = static_cast<double>(raw);
      if (!std::isfinite(v)) return;
      max_abs = std::max(max_abs, std::abs(v));
      if (v != 0.0) min_nonzero = std::min(min_nonzero, v);
    });
    double unit_s = is_integer(ft->datatype) ? 1e-9 : 1.0;  // integer offsets: ns (Ouster `t`)
    const bool absolute = named_absolute || max_abs * unit_s > 1e3;
    if (absolute) unit_s = absolute_time_unit_s(max_abs);
    // Absolute stamps: no-return cells of organized scans carry a zero stamp (pcd_os128 does),
    // so the sweep start is the earliest non-zero stamp and zero stamps get offset 0.
    double t0 = 0.0;
    if (absolute) {
      t0 = std::isfinite(min_nonzero) ? min_nonzero : 0.0;
      cloud.stamp_s = t0 * unit_s;
    }
    visit(*ft, n, [&](std::size_t i, auto raw) {
      const double v = static_cast<double>(raw);
      const bool known = std::isfinite(v) && !(absolute && v == 0.0);
      pts[i].time = known ? static_cast<float>((v - t0) * unit_s) : 0.f;
    });
    cloud.fields.time = true;
  }

  // NaN coordinates: no-returns of an organized scan, errors otherwise.
  const bool organized = height > 1;
  std::size_t nan_count = 0;
  for (std::size_t i = 0; i < n; ++i) {
    Point& p = pts[i];
    if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) continue;
    if (!organized)
      throw Error(source + ": point " + std::to_string(i) +
                  " has a NaN or infinite coordinate (unorganized cloud)");
    p.x = p.y = p.z = 0.f;
    ++nan_count;
  }
  if (n > 0 && nan_count == n) throw Error(source + ": every point has NaN coordinates");
  return cloud;
}

pcl::PCLPointCloud2 to_pcl_cloud2(const PointCloud& cloud, bool time_offsets) {
  pcl::PCLPointCloud2 blob;
  auto add = [&](const char* name, std::uint8_t type) {
    Field f;
    f.name = name;
    f.offset = blob.point_step;
    f.datatype = type;
    f.count = 1;
    blob.fields.push_back(f);
    blob.point_step += static_cast<std::uint32_t>(type_size(type));
  };
  add("x", Field::FLOAT32);
  add("y", Field::FLOAT32);
  add("z", Field::FLOAT32);
  add("intensity", Field::FLOAT32);
  const bool ring = cloud.fields.ring;
  const bool absolute = cloud.fields.time && cloud.stamp_s != 0.0 && !time_offsets;
  const bool offsets = cloud.fields.time && !absolute;
  const bool label = cloud.has_labels();
  std::uint32_t ring_at = 0, time_at = 0, label_at = 0;
  if (ring) {
    ring_at = blob.point_step;
    add("ring", Field::UINT16);
  }
  if (offsets) {
    time_at = blob.point_step;
    add("time", Field::FLOAT32);
  }
  if (absolute) {
    time_at = blob.point_step;
    add("timestamp", Field::FLOAT64);
  }
  if (label) {
    label_at = blob.point_step;
    add("label", Field::UINT32);
  }
  const std::size_t n = cloud.size();
  const bool organized = cloud.is_organized();
  blob.width = organized ? cloud.width : static_cast<std::uint32_t>(n);
  blob.height = organized ? cloud.height : 1;
  blob.row_step = blob.point_step * blob.width;
  blob.is_dense = true;
  blob.data.resize(n * blob.point_step);
  std::uint8_t* out = blob.data.data();
  for (std::size_t i = 0; i < n; ++i, out += blob.point_step) {
    const Point& p = cloud.points[i];
    const float xyzi[4] = {p.x, p.y, p.z, p.intensity};
    std::memcpy(out, xyzi, sizeof(xyzi));
    if (ring) std::memcpy(out + ring_at, &p.ring, sizeof(p.ring));
    if (offsets) std::memcpy(out + time_at, &p.time, sizeof(p.time));
    if (absolute) {
      const double t = cloud.stamp_s + p.time;
      std::memcpy(out + time_at, &t, sizeof(t));
    }
    if (label) std::memcpy(out + label_at, &cloud.labels[i], sizeof(std::uint32_t));
  }
  return blob;
}

std::string ascii_values(const pcl::PCLPointCloud2& blob) {
  std::string body;
  const std::size_t n = std::size_t(blob.width) * blob.height;
  body.reserve(n * blob.fields.size() * 12);
  char buf[40];
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint8_t* p = blob.data.data() + i * blob.point_step;
    for (std::size_t k = 0; k < blob.fields.size(); ++k) {
      const auto& f = blob.fields[k];
      int len = 0;
      if (f.datatype == Field::FLOAT32) {
        float v;
        std::memcpy(&v, p + f.offset, 4);
        len = std::snprintf(buf, sizeof(buf), "%.9g", v);  // 9 digits: float32 round-trips
      } else if (f.datatype == Field::FLOAT64) {
        double v;
        std::memcpy(&v, p + f.offset, 8);
        len = std::snprintf(buf, sizeof(buf), "%.17g", v);
      } else if (f.datatype == Field::UINT16) {
        std::uint16_t v;
        std::memcpy(&v, p + f.offset, 2);
        len = std::snprintf(buf, sizeof(buf), "%u", unsigned(v));
      } else {
        std::uint32_t v;
        std::memcpy(&v, p + f.offset, 4);
        len = std::snprintf(buf, sizeof(buf), "%u", v);
      }
      body.append(buf, static_cast<std::size_t>(len));
      body += k + 1 == blob.fields.size() ? '\n' : ' ';
    }
  }
  return body;
}

}  // namespace fieldlidar::io::detail
