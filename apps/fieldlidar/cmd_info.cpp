// fieldlidar info FILE [--json]: what a LiDAR file holds.

#include <cstdio>
#include <memory>
#include <string>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "fieldlidar/io/cloud_file.hpp"

namespace fieldlidar::app {

namespace {
struct InfoOptions {
  std::string input;
  bool json = false;
};

nlohmann::json describe(const std::string& path) {
  const auto format = io::cloud_format_of(path);
  const PointCloud cloud = io::read_cloud(path);
  const auto bounds = compute_bounds(cloud);
  nlohmann::json fields = nlohmann::json::array({"x", "y", "z"});
  if (cloud.fields.intensity) fields.push_back("intensity");
  if (cloud.fields.ring) fields.push_back("ring");
  if (cloud.fields.time) fields.push_back("time");
  if (cloud.fields.label) fields.push_back("label");
  nlohmann::json j;
  j["file"] = path;
  j["format"] = io::to_string(*format);
  j["frames"] = 1;
  j["points"] = cloud.size();
  j["valid_points"] = cloud.valid_count();
  j["fields"] = fields;
  j["rings"] = cloud.fields.ring ? cloud.ring_count() : 0;
  if (cloud.is_organized()) j["organized"] = {{"width", cloud.width}, {"height", cloud.height}};
  if (!bounds.empty())
    j["bounds"] = {{"min", {bounds.min.x(), bounds.min.y(), bounds.min.z()}},
                   {"max", {bounds.max.x(), bounds.max.y(), bounds.max.z()}}};
  return j;
}

void print_text(const nlohmann::json& j) {
  fmt::print("file:    {}\n", j["file"].get<std::string>());
  fmt::print("format:  {}\n", j["format"].get<std::string>());
  fmt::print("frames:  {}\n", j["frames"].get<long>());
  fmt::print("points:  {} ({} valid)\n", j["points"].get<long>(), j["valid_points"].get<long>());
  std::string fields;
  for (const auto& f : j["fields"]) fields += (fields.empty() ? "" : " ") + f.get<std::string>();
  fmt::print("fields:  {}\n", fields);
  fmt::print("rings:   {}\n", j["rings"].get<long>());
  if (j.contains("bounds")) {
    const auto& lo = j["bounds"]["min"];
    const auto& hi = j["bounds"]["max"];
    fmt::print("bounds:  x [{:.3f}, {:.3f}]  y [{:.3f}, {:.3f}]  z [{:.3f}, {:.3f}] m\n",
               lo[0].get<double>(), hi[0].get<double>(), lo[1].get<double>(), hi[1].get<double>(),
               lo[2].get<double>(), hi[2].get<double>());
  }
}
}  // namespace

void add_info_command(CLI::App& app) {
  auto opts = std::make_shared<InfoOptions>();
  auto* cmd = app.add_subcommand(
      "info", "Show format, frame and point counts, fields, bounds and rings of a LiDAR file");
  cmd->add_option("FILE", opts->input, "Input file (.bin KITTI, .pcd, .ply, .las)")->required();
  cmd->add_flag("--json", opts->json,
                "Print machine-readable JSON (keys: format, frames, points, ...)");
  cmd->callback([opts] {
    const auto j = describe(opts->input);
    if (opts->json)
      std::printf("%s\n", j.dump(2).c_str());
    else
      print_text(j);
  });
}

}  // namespace fieldlidar::app
