// fieldlidar demo: the built-in default job, run when no command is given.

#include <filesystem>
#include <memory>
#include <string>

#include <fmt/core.h>

#include "commands.hpp"
#include "fieldlidar/io/cloud_file.hpp"

namespace fieldlidar::app {

namespace {
struct DemoOptions {
  std::string data_dir = FIELDLIDAR_DEFAULT_DATA_DIR;
};
}  // namespace

void add_demo_command(CLI::App& app) {
  auto opts = std::make_shared<DemoOptions>();
  auto* cmd = app.add_subcommand("demo", "Run the built-in demonstration (the default job)");
  cmd->add_option("--data-dir", opts->data_dir, "Folder of real recorded data")
      ->capture_default_str();
  cmd->callback([opts] {
    const auto scan = std::filesystem::path(opts->data_dir) / "kitti00" / "000000.bin";
    const PointCloud cloud = io::read_cloud(scan);
    const auto b = compute_bounds(cloud);
    fmt::print("fieldlidar demo: {} -> {} points, x [{:.1f}, {:.1f}] m, y [{:.1f}, {:.1f}] m\n",
               scan.string(), cloud.size(), b.min.x(), b.max.x(), b.min.y(), b.max.y());
  });
}

}  // namespace fieldlidar::app
