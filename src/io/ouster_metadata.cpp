// Ouster sensor metadata JSON -> OusterMetadata (flat pre-2.0 layout and nested 2.x layout).
#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>

#include <nlohmann/json.hpp>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/ouster.hpp"

namespace fieldlidar::io {
namespace {

using Json = nlohmann::json;

/// The first of `keys` found in `objects` (searched in order), or nullptr.
const Json* find(const std::vector<const Json*>& objects, const std::string& key) {
  for (const Json* o : objects)
    if (o && o->is_object() && o->contains(key) && !(*o)[key].is_null()) return &(*o)[key];
  return nullptr;
}

const Json* child(const Json& j, const std::string& key) {
  return j.is_object() && j.contains(key) && j[key].is_object() ? &j[key] : nullptr;
}

}  // namespace

std::string to_string(OusterProfile profile) {
  return profile == OusterProfile::kLegacy ? "LEGACY" : "RNG19_RFL8_SIG16_NIR16";
}

OusterMetadata parse_ouster_metadata(std::string_view json_text, const std::string& source) {
  Json j;
  try {
    j = Json::parse(json_text);
  } catch (const std::exception& e) {
    throw Error(source + ": not valid JSON (" + e.what() + ")");
  }
  if (!j.is_object()) throw Error(source + ": Ouster metadata must be a JSON object");
  // Nested layout (firmware 2.x clients) or flat layout (older clients, and 2.2+ "legacy" output).
  const std::vector<const Json*> objs = {child(j, "beam_intrinsics"),
                                         child(j, "lidar_intrinsics"),
                                         child(j, "lidar_data_format"),
                                         child(j, "data_format"),
                                         child(j, "config_params"),
                                         child(j, "sensor_info"),
                                         &j};
  auto fail = [&](const std::string& what) -> Error { return Error(source + ": " + what); };
  OusterMetadata m;
  try {
    auto str = [&](const char* key) {
      const Json* v = find(objs, key);
      return v && v->is_string() ? v->get<std::string>() : std::string();
    };
    m.prod_line = str("prod_line");
    m.prod_sn = str("prod_sn");
    m.firmware = str("build_rev");
    m.lidar_mode = str("lidar_mode");
    if (const Json* v = find(objs, "initialization_id"); v && v->is_number_unsigned())
      m.initialization_id = v->get<std::uint32_t>();

    const Json* alt = find(objs, "beam_altitude_angles");
    const Json* azi = find(objs, "beam_azimuth_angles");
    if (!alt || !alt->is_array()) throw fail("field 'beam_altitude_angles' is missing");
    if (!azi || !azi->is_array()) throw fail("field 'beam_azimuth_angles' is missing");
    m.beam_altitude_deg = alt->get<std::vector<double>>();
    m.beam_azimuth_deg = azi->get<std::vector<double>>();
    const std::size_t h = m.beam_altitude_deg.size();
    if (h == 0 || h > 256 || m.beam_azimuth_deg.size() != h)
      throw fail("'beam_altitude_angles' (" + std::to_string(h) + ") and 'beam_azimuth_angles' (" +
                 std::to_string(m.beam_azimuth_deg.size()) + ") must have one entry per beam");
    for (std::size_t b = 0; b < h; ++b)
      if (!std::isfinite(m.beam_altitude_deg[b]) || std::abs(m.beam_altitude_deg[b]) > 90 ||
          !std::isfinite(m.beam_azimuth_deg[b]) || std::abs(m.beam_azimuth_deg[b]) > 45)
        throw fail("beam " + std::to_string(b) + " has an impossible angle");

    // Defaults of the OS-1 (ouster-sdk's defaults for metadata that predates these fields).
    m.lidar_origin_to_beam_origin_mm = 12.163;
    m.lidar_to_sensor_transform << -1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1, 36.18, 0, 0, 0, 1;
    if (const Json* v = find(objs, "lidar_origin_to_beam_origin_mm"); v && v->is_number())
      m.lidar_origin_to_beam_origin_mm = v->get<double>();
    if (const Json* v = find(objs, "lidar_to_sensor_transform")) {
      const auto t = v->get<std::vector<double>>();
      if (t.size() != 16) throw fail("'lidar_to_sensor_transform' must have 16 numbers");
      for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) m.lidar_to_sensor_transform(r, c) = t[std::size_t(r * 4 + c)];
    }

    int mode_columns = 0;
    if (!m.lidar_mode.empty()) {
      const auto x = m.lidar_mode.find('x');
      if (x == std::string::npos) throw fail("'lidar_mode' = '" + m.lidar_mode + "' is not WxR");
      mode_columns = std::stoi(m.lidar_mode.substr(0, x));
      m.rotation_rate_hz = std::stod(m.lidar_mode.substr(x + 1));
    }
    auto integer = [&](const char* key, int fallback) {
      const Json* v = find(objs, key);
      return v && v->is_number_integer() ? v->get<int>() : fallback;
    };
    m.columns_per_frame = integer("columns_per_frame", mode_columns ? mode_columns : 1024);
    m.columns_per_packet = integer("columns_per_packet", 16);
    m.pixels_per_column = integer("pixels_per_column", int(h));
    m.column_window_first = 0;
    m.column_window_last = m.columns_per_frame - 1;
    if (const Json* v = find(objs, "column_window"); v && v->is_array() && v->size() == 2) {
      m.column_window_first = (*v)[0].get<int>();
      m.column_window_last = (*v)[1].get<int>();
    }
    m.udp_port_lidar = std::uint16_t(integer("udp_port_lidar", 7502));
    m.udp_port_imu = std::uint16_t(integer("udp_port_imu", 7503));
    const std::string profile = str("udp_profile_lidar");
    if (profile.empty() || profile == "LEGACY")
      m.profile = OusterProfile::kLegacy;
    else if (profile == "RNG19_RFL8_SIG16_NIR16")
      m.profile = OusterProfile::kRng19Rfl8Sig16Nir16;
    else
      throw fail("'udp_profile_lidar' = '" + profile +
                 "' is not supported (LEGACY, RNG19_RFL8_SIG16_NIR16)");
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw fail(std::string("malformed Ouster metadata (") + e.what() + ")");
  }
  const int w = m.columns_per_frame;
  if (w != 512 && w != 1024 && w != 2048 && w != 4096)
    throw fail("'columns_per_frame' = " + std::to_string(w) + " (expected 512/1024/2048/4096)");
  if (m.columns_per_packet < 1 || m.columns_per_packet > 64)
    throw fail("'columns_per_packet' = " + std::to_string(m.columns_per_packet) + " out of range");
  if (std::size_t(m.pixels_per_column) != m.beam_altitude_deg.size())
    throw fail("'pixels_per_column' = " + std::to_string(m.pixels_per_column) + " but " +
               std::to_string(m.beam_altitude_deg.size()) + " beam angles");
  if (m.column_window_first < 0 || m.column_window_first >= w || m.column_window_last < 0 ||
      m.column_window_last >= w)
    throw fail("'column_window' lies outside [0, columns_per_frame)");
  if (!(m.rotation_rate_hz > 0 && m.rotation_rate_hz <= 100))
    throw fail("'lidar_mode' = '" + m.lidar_mode + "' has an impossible rotation rate");
  return m;
}

OusterMetadata read_ouster_metadata(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw Error(path.string() + ": cannot open Ouster metadata");
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_ouster_metadata(ss.str(), path.string());
}

SensorModel sensor_model_of(const OusterMetadata& meta) {
  std::vector<double> alt;
  for (double d : meta.beam_altitude_deg) alt.push_back(d * std::numbers::pi / 180.0);
  std::string name = meta.prod_line.empty() ? "ouster" : meta.prod_line;
  const bool os0 = name.find("OS-0") != std::string::npos;
  const bool os2 = name.find("OS-2") != std::string::npos;
  const double max_range_m = os0 ? 50.0 : os2 ? 240.0 : 120.0;
  auto m = SensorModel::from_beam_angles(name, alt, meta.columns_per_frame, meta.rotation_rate_hz,
                                         os2 ? 0.5 : 0.3, max_range_m);
  m.beam_origin_offset_m = meta.lidar_origin_to_beam_origin_mm * 1e-3;
  // Azimuth offsets follow the rings (sorted by altitude).
  std::vector<std::size_t> order(alt.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return meta.beam_altitude_deg[a] < meta.beam_altitude_deg[b];
  });
  for (std::size_t r = 0; r < order.size(); ++r)
    m.beam_azimuth_offsets_rad.push_back(-meta.beam_azimuth_deg[order[r]] * std::numbers::pi /
                                         180.0);
  m.range_accuracy_m = 0.03;
  return m;
}

}  // namespace fieldlidar::io
