// fieldlidar convert IN OUT: convert between point-cloud file formats, chosen by extension.

#include <memory>
#include <string>

#include <fmt/core.h>

#include "commands.hpp"
#include "fieldlidar/io/cloud_file.hpp"

namespace fieldlidar::app {

namespace {
struct ConvertOptions {
  std::string input;
  std::string output;
  bool force = false;
  bool ascii = false;
  bool compressed = false;
};
}  // namespace

void add_convert_command(CLI::App& app) {
  auto opts = std::make_shared<ConvertOptions>();
  auto* cmd =
      app.add_subcommand("convert", "Convert a LiDAR file to another format (by extension)");
  cmd->add_option("IN", opts->input, "Input file (.bin, .pcd, .ply, .las)")->required();
  cmd->add_option("OUT", opts->output, "Output file (.bin, .pcd, .ply)")->required();
  cmd->add_flag("-f,--force", opts->force, "Replace OUT if it already exists");
  cmd->add_flag("--ascii", opts->ascii, "Write ASCII PCD/PLY instead of binary");
  cmd->add_flag("--compressed", opts->compressed, "Write PCD as binary_compressed");
  cmd->callback([opts] {
    const PointCloud cloud = io::read_cloud(opts->input);
    io::WriteOptions w;
    w.overwrite = opts->force;
    w.binary = !opts->ascii;
    w.compressed = opts->compressed;
    io::write_cloud(opts->output, cloud, w);
    fmt::print("wrote {} points to {}\n", cloud.size(), opts->output);
  });
}

}  // namespace fieldlidar::app
