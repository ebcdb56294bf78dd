// fieldlidar demo: the built-in default job, run when no command is given. It runs the seed 000
// closed loop in simulation (the mower follows its operator and records the lawn boundary) and,
// when the real data is present, scores ground segmentation on a real off-road scan.

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>

#include <fmt/core.h>

#include "commands.hpp"
#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/cloud_file.hpp"
#include "fieldlidar/io/label_file.hpp"
#include "fieldlidar/segmentation/segment.hpp"
#include "follow_job.hpp"

namespace fieldlidar::app {

namespace {

namespace fs = std::filesystem;

/// The real data folder: $FIELDLIDAR_DATA_DIR when set, else the one found at build time.
std::string default_data_dir() {
  const char* env = std::getenv("FIELDLIDAR_DATA_DIR");
  return env && *env ? std::string(env) : std::string(FIELDLIDAR_DEFAULT_DATA_DIR);
}

struct DemoOptions {
  std::string data_dir = default_data_dir();
  std::string out;
};

/// `base`, or `base_2`, `base_3`, ... : the first name not taken, so a demo never replaces
/// anything that is already there.
fs::path fresh_folder(const fs::path& base) {
  if (!fs::exists(base)) return base;
  for (int i = 2;; ++i) {
    fs::path p = base;
    p += "_" + std::to_string(i);
    if (!fs::exists(p)) return p;
  }
}

/// The real scan of part 2 and its labels.
fs::path real_scan(const fs::path& data_dir) {
  return data_dir / "rellis3d" / "000001.bin";
}
fs::path real_labels(const fs::path& data_dir) {
  return data_dir / "rellis3d" / "000001.label";
}

void score_real_ground(const fs::path& data_dir) {
  const fs::path scan = real_scan(data_dir), truth = real_labels(data_dir);
  if (!fs::exists(scan) || !fs::exists(truth)) {
    fmt::print("\n[2/2] real off-road scan skipped: {} is absent\n", scan.string());
    return;
  }
  const PointCloud cloud = io::read_cloud(scan);
  const auto labels = io::read_labels(truth, cloud.size());
  SensorModel sensor = SensorModel::os1_64();
  sensor.columns = 2048;  // RELLIS-3D's Ouster ran in 2048 x 10 mode
  fmt::print(
      "\n[2/2] ground segmentation on a real off-road scan (RELLIS-3D, Ouster OS1-64, {} "
      "points) against its labels\n",
      cloud.size());
  fmt::print("      method    precision  recall  F1      time\n");
  for (const auto& [name, method] : {std::pair{"robust", segmentation::GroundMethod::kRobust},
                                     std::pair{"seed000", segmentation::GroundMethod::kSeed000},
                                     std::pair{"seed002", segmentation::GroundMethod::kSeed002}}) {
    segmentation::GroundConfig cfg;
    cfg.method = method;
    const auto t0 = std::chrono::steady_clock::now();
    const auto r = segmentation::segment_ground(cloud, sensor, cfg);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    const auto s = segmentation::score_ground(cloud, r.is_ground, labels,
                                              segmentation::rellis_ground_classes(),
                                              segmentation::rellis_ignored_classes());
    fmt::print("      {:<9} {:.3f}      {:.3f}   {:.3f}   {:.1f} ms\n", name, s.precision, s.recall,
               s.f1, ms);
  }
}

}  // namespace

void add_demo_command(CLI::App& app) {
  auto opts = std::make_shared<DemoOptions>();
  auto* cmd = app.add_subcommand(
      "demo",
      "Run the built-in demonstration (the default job): a simulated mower follows its "
      "operator around a lawn and records the boundary; ground segmentation is scored on "
      "a real scan");
  auto* data_dir =
      cmd->add_option(
             "--data-dir", opts->data_dir,
             "Folder of real recorded data ($FIELDLIDAR_DATA_DIR overrides the built-in default)")
          ->capture_default_str();
  cmd->add_option("--out", opts->out,
                  "Output folder (default: ./fieldlidar_demo, or _2, _3, ... if that exists)");
  cmd->callback([opts, data_dir] {
    // A folder given on the command line must hold the real scan: part 2 is skipped quietly only
    // for the default folder (the environment's or the build's), which may be absent.
    if (data_dir->count() > 0)
      for (const auto& f : {real_scan(opts->data_dir), real_labels(opts->data_dir)})
        if (!fs::is_regular_file(f))
          throw Error("--data-dir " + opts->data_dir + ": " + f.string() +
                      " does not exist (the real scan of the demo's part 2)");
    const fs::path out = opts->out.empty() ? fresh_folder("fieldlidar_demo") : fs::path(opts->out);
    fmt::print("[1/2] seed 000: simulated VLP-16 mower follows its operator around a lawn\n");
    FollowOptions follow;
    follow.out = out.string();
    run_follow(follow);
    score_real_ground(opts->data_dir);
    fmt::print("\nOpen {}/follow.png for the picture; boundary.geojson is the lawn polygon.\n",
               out.string());
  });
}

}  // namespace fieldlidar::app
