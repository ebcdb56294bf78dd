// fieldlidar info INPUT [--json]: what a LiDAR file, folder, capture or bag holds.

#include <algorithm>
#include <cstdio>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "fieldlidar/io/cloud_file.hpp"
#include "fieldlidar/io/frame_source.hpp"
#include "fieldlidar/io/las.hpp"
#include "fieldlidar/io/rosbag_reader.hpp"
#include "support/warnings.hpp"

namespace fieldlidar::app {

namespace {
struct InfoOptions {
  std::string input;
  std::string topic;
  std::string metadata;
  bool json = false;
};

bool is_bag(const std::string& path) {
  return io::extension_of(path) == "bag";
}

/// Bag topics as JSON; returns the scan topic to read frames from ("" when none or ambiguous).
std::string describe_topics(const std::string& path, const std::string& wanted, nlohmann::json& j) {
  const auto topics = io::bag_topics(path);
  nlohmann::json counts = nlohmann::json::object(), types = nlohmann::json::object();
  std::vector<std::string> scans;
  std::size_t scan_messages = 0;
  for (const auto& t : topics) {
    counts[t.name] = t.messages;
    types[t.name] = t.datatype;
    if (t.datatype == "sensor_msgs/LaserScan" || t.datatype == "sensor_msgs/PointCloud2") {
      scans.push_back(t.name);
      scan_messages += t.messages;
    }
  }
  j["topics"] = counts;
  j["topic_types"] = types;
  j["frames"] = scan_messages;
  if (!wanted.empty()) return wanted;
  return scans.size() == 1 ? scans.front() : std::string();
}

nlohmann::json describe(const InfoOptions& opts) {
  nlohmann::json j;
  j["file"] = opts.input;
  io::SourceOptions so;
  so.metadata = opts.metadata;
  if (is_bag(opts.input)) {
    so.topic = describe_topics(opts.input, opts.topic, j);
    if (so.topic.empty()) {  // several scan topics: counts only
      j["format"] = "rosbag";
      j["points"] = 0;
      j["valid_points"] = 0;
      j["fields"] = nlohmann::json::array();
      j["rings"] = nullptr;
      j["note"] = "several scan topics; pass --topic to read one";
      return j;
    }
    j["topic"] = so.topic;
  }
  auto source = io::FrameSource::open(opts.input, so);
  std::size_t frames = 0, partial = 0, points = 0, valid = 0, rings = 0;
  std::size_t min_pts = std::numeric_limits<std::size_t>::max(), max_pts = 0;
  double first_stamp = 0, last_stamp = 0;
  double first_full_s = 0, last_full_s = 0;  // stamps of the first and last full sweeps
  PointFields fields;
  Bounds3 bounds;
  std::optional<std::pair<std::uint32_t, std::uint32_t>> organized;
  std::map<std::uint32_t, std::size_t> label_counts;
  std::optional<Eigen::Vector3d> origin;  // a georeferenced cloud's origin (PointCloud::origin_m)
  while (auto f = source->next()) {
    const PointCloud& c = f->cloud;
    if (!c.origin_m.isZero()) origin = c.origin_m;
    for (const auto label : c.labels) ++label_counts[label];
    (f->complete ? frames : partial) += 1;
    if (frames + partial == 1) first_stamp = f->stamp_s;
    last_stamp = f->stamp_s;
    if (f->complete) {
      if (frames == 1) first_full_s = f->stamp_s;
      last_full_s = f->stamp_s;
    }
    points += c.size();
    valid += c.valid_count();
    min_pts = std::min(min_pts, c.size());
    max_pts = std::max(max_pts, c.size());
    fields.intensity |= c.fields.intensity;
    fields.ring |= c.fields.ring;
    fields.time |= c.fields.time;
    fields.label |= c.fields.label;
    if (c.fields.ring) rings = std::max(rings, c.ring_count());
    const auto b = compute_bounds(c);
    if (!b.empty()) bounds.extend(b.min), bounds.extend(b.max);
    if (c.is_organized()) organized = std::make_pair(c.width, c.height);
  }
  nlohmann::json field_names = nlohmann::json::array({"x", "y", "z"});
  if (fields.intensity) field_names.push_back("intensity");
  if (fields.ring) field_names.push_back("ring");
  if (fields.time) field_names.push_back("time");
  if (fields.label) field_names.push_back("label");
  j["format"] = source->format();
  j["frames"] = frames;
  j["points"] = points;
  j["valid_points"] = valid;
  j["fields"] = field_names;
  // No ring field (or no point): the number of rings is unknown, not 0.
  j["rings"] = rings > 0 ? nlohmann::json(rings) : nlohmann::json(nullptr);
  if (partial) j["partial_frames"] = partial;
  if (const auto s = source->sensor()) j["sensor"] = s->name;
  if (origin) j["origin_m"] = {origin->x(), origin->y(), origin->z()};
  if (organized) j["organized"] = {{"width", organized->first}, {"height", organized->second}};
  if (!bounds.empty())
    j["bounds"] = {{"min", {bounds.min.x(), bounds.min.y(), bounds.min.z()}},
                   {"max", {bounds.max.x(), bounds.max.y(), bounds.max.z()}}};
  const std::size_t all = frames + partial;
  if (all > 1) {
    j["per_frame"] = {{"points_min", min_pts},
                      {"points_mean", double(points) / double(all)},
                      {"points_max", max_pts}};
    if (last_stamp > first_stamp) {  // files without stamps have no period to report
      j["per_frame"]["period_s_mean"] = frames > 1
                                            ? (last_full_s - first_full_s) / double(frames - 1)
                                            : (last_stamp - first_stamp) / double(all - 1);
      j["per_frame"]["duration_s"] = last_stamp - first_stamp;
    }
  }
  if (!label_counts.empty() && label_counts.size() <= 256) {
    nlohmann::json counts;
    for (const auto& [label, count] : label_counts) counts[std::to_string(label)] = count;
    j["label_counts"] = counts;
  }
  if (j["format"] == "las") {
    // read_cloud() returns LAS points relative to a local origin; report it and the header.
    const auto header = io::read_las_header(opts.input);
    const auto origin = io::las_local_origin(header);
    j["las"] = {{"version",
                 std::to_string(header.version_major) + "." + std::to_string(header.version_minor)},
                {"point_format", header.point_format},
                {"scale", {header.scale.x(), header.scale.y(), header.scale.z()}},
                {"offset", {header.offset.x(), header.offset.y(), header.offset.z()}},
                {"origin_m", {origin.x(), origin.y(), origin.z()}},
                {"header_min", {header.min.x(), header.min.y(), header.min.z()}},
                {"header_max", {header.max.x(), header.max.y(), header.max.z()}}};
  }
  const double inf = std::numeric_limits<double>::infinity();
  if (const auto imu = source->imu_until(inf).size()) j["imu_samples"] = imu;
  if (const auto odom = source->odometry_until(inf).size()) j["odometry_samples"] = odom;
  if (const auto w = source->warnings(); !w.empty()) j["warnings"] = w;
  return j;
}

void print_text(const nlohmann::json& j) {
  fmt::print("file:    {}\n", j["file"].get<std::string>());
  fmt::print("format:  {}\n", j["format"].get<std::string>());
  if (j.contains("sensor")) fmt::print("sensor:  {}\n", j["sensor"].get<std::string>());
  if (j.contains("topic")) fmt::print("topic:   {}\n", j["topic"].get<std::string>());
  fmt::print("frames:  {}", j["frames"].get<long>());
  if (j.contains("partial_frames"))
    fmt::print(" (+{} partial sweeps at the capture's ends)", j["partial_frames"].get<long>());
  fmt::print("\n");
  fmt::print("points:  {} ({} valid)\n", j["points"].get<long>(), j["valid_points"].get<long>());
  if (j.contains("per_frame")) {
    const auto& p = j["per_frame"];
    fmt::print("per frame: {} .. {} points (mean {:.0f})", p["points_min"].get<long>(),
               p["points_max"].get<long>(), p["points_mean"].get<double>());
    if (p.contains("period_s_mean"))
      fmt::print(", period {:.4f} s, span {:.3f} s", p["period_s_mean"].get<double>(),
                 p["duration_s"].get<double>());
    fmt::print("\n");
  }
  std::string fields;
  for (const auto& f : j["fields"]) fields += (fields.empty() ? "" : " ") + f.get<std::string>();
  fmt::print("fields:  {}\n", fields);
  fmt::print("rings:   {}\n", j["rings"].is_null() ? std::string("unknown (no ring field)")
                                                   : std::to_string(j["rings"].get<long>()));
  if (j.contains("bounds")) {
    const auto& lo = j["bounds"]["min"];
    const auto& hi = j["bounds"]["max"];
    fmt::print("bounds:  x [{:.3f}, {:.3f}]  y [{:.3f}, {:.3f}]  z [{:.3f}, {:.3f}] m\n",
               lo[0].get<double>(), hi[0].get<double>(), lo[1].get<double>(), hi[1].get<double>(),
               lo[2].get<double>(), hi[2].get<double>());
  }
  if (j.contains("origin_m"))
    fmt::print("origin:  ({:.3f}, {:.3f}, {:.3f}) m (georeference: absolute = origin + point)\n",
               j["origin_m"][0].get<double>(), j["origin_m"][1].get<double>(),
               j["origin_m"][2].get<double>());
  if (j.contains("las")) {
    const auto& l = j["las"];
    fmt::print(
        "las:     version {}, point format {}, bounds relative to origin ({:.0f}, {:.0f}, {:.0f}) "
        "m\n",
        l["version"].get<std::string>(), l["point_format"].get<int>(),
        l["origin_m"][0].get<double>(), l["origin_m"][1].get<double>(),
        l["origin_m"][2].get<double>());
  }
  if (j.contains("label_counts")) {
    fmt::print("labels: ");
    for (const auto& [label, count] : j["label_counts"].items())
      fmt::print(" {}:{}", label, count.get<long>());
    fmt::print("\n");
  }
  if (j.contains("imu_samples")) fmt::print("imu:     {} samples\n", j["imu_samples"].get<long>());
  if (j.contains("odometry_samples"))
    fmt::print("odometry: {} samples\n", j["odometry_samples"].get<long>());
  if (j.contains("topics")) {
    fmt::print("topics:\n");
    for (const auto& [name, count] : j["topics"].items())
      fmt::print("  {:<32} {:>8}  {}\n", name, count.get<long>(),
                 j["topic_types"][name].get<std::string>());
  }
  if (j.contains("note")) fmt::print("note:    {}\n", j["note"].get<std::string>());
}

/// Warnings go to stderr in both output modes (the JSON holds them too, under "warnings").
void warn_all(const nlohmann::json& j) {
  if (j.contains("warnings"))
    for (const auto& w : j["warnings"]) warn(w.get<std::string>());
}
}  // namespace

void add_info_command(CLI::App& app) {
  auto opts = std::make_shared<InfoOptions>();
  auto* cmd = app.add_subcommand(
      "info", "Show format, frame and point counts, fields, bounds and rings of a LiDAR input");
  cmd->add_option("INPUT", opts->input,
                  "Input: .bin/.pcd/.ply/.las file, folder or glob of them, Velodyne or Ouster "
                  ".pcap, ROS1 .bag")
      ->required();
  cmd->add_option("--topic", opts->topic, "Bag topic of the scans (default: the only one)");
  cmd->add_option("--metadata", opts->metadata,
                  "Ouster metadata JSON (default: <capture>.json beside the capture)");
  cmd->add_flag("--json", opts->json,
                "Print machine-readable JSON (keys: format, frames, points, ...)");
  cmd->callback([opts] {
    const auto j = describe(*opts);
    if (j.value("points", 0L) == 0 && !j.contains("note"))
      warn(fmt::format("{} holds no points", opts->input));
    if (opts->json)
      std::printf("%s\n", j.dump(2).c_str());
    else
      print_text(j);
    warn_all(j);
  });
}

}  // namespace fieldlidar::app
