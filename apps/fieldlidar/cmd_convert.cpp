// fieldlidar convert IN OUT: convert a cloud file to another format, or a capture, bag, folder or
// glob into a folder of one file per frame.

#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include <fmt/core.h>

#include "commands.hpp"
#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/cloud_file.hpp"
#include "fieldlidar/io/file_util.hpp"
#include "fieldlidar/io/frame_source.hpp"
#include "support/option_checks.hpp"
#include "support/progress_line.hpp"
#include "support/warnings.hpp"

namespace fieldlidar::app {

namespace {
struct ConvertOptions {
  std::string input;
  std::string output;
  std::string format = "pcd";
  std::string topic;
  std::string metadata;
  bool force = false;
  bool ascii = false;
  bool compressed = false;
  bool partial = false;
  bool quiet = false;
};

/// A one-line progress bar on stderr, drawn only when stderr is a terminal (progress_line.hpp).
class ProgressBar {
 public:
  explicit ProgressBar(bool enabled) : enabled_(enabled && stderr_is_terminal()) {}
  void update(double fraction, std::size_t frames) {
    if (!enabled_) return;
    const int width = 40;
    const int filled = int(fraction * width + 0.5);
    std::fprintf(
        stderr, "\r[%s%s] %3d%%  %zu frames", std::string(std::size_t(filled), '#').c_str(),
        std::string(std::size_t(width - filled), '.').c_str(), int(fraction * 100 + 0.5), frames);
    std::fflush(stderr);
  }
  void done() {
    if (enabled_) std::fprintf(stderr, "\n");
  }

 private:
  bool enabled_;
};

/// Tells where a georeferenced cloud's origin went (PointCloud::origin_m: a LAS offset): kept in
/// PCD and PLY, which store the points relative to it; lost in KITTI .bin, which has no header.
void report_origin(const PointCloud& cloud, const std::string& output) {
  if (cloud.origin_m.isZero()) return;
  const auto& o = cloud.origin_m;
  const std::string where = fmt::format("({:.3f}, {:.3f}, {:.3f}) m", o.x(), o.y(), o.z());
  const auto format = io::cloud_format_of(output);
  if (format == io::CloudFormat::kKittiBin) {
    warn(
        "KITTI .bin has no place for the georeference: the points are written relative to the "
        "origin " +
        where + " (absolute = origin + point), which is not kept; write .pcd or " +
        ".ply to keep it");
    return;
  }
  fmt::print(
      "kept the georeference: points relative to the origin {} (absolute = origin + point), "
      "stored as the {}\n",
      where,
      format == io::CloudFormat::kPly ? "PLY header comment 'fieldlidar origin_m X Y Z'"
                                      : "PCD VIEWPOINT translation");
}

bool single_file_conversion(const ConvertOptions& o) {
  namespace fs = std::filesystem;
  const fs::path in(o.input);
  return fs::is_regular_file(in) && io::cloud_format_of(in) && io::cloud_format_of(o.output) &&
         !fs::is_directory(o.output);
}

/// Refuses options the conversion would not use: --format for one output file (its extension
/// chooses), an encoding the output format does not have, an output file name for a sequence of
/// frames, an output extension that is no cloud format.
void check_convert_options(const ConvertOptions& o, bool format_given) {
  namespace fs = std::filesystem;
  const fs::path in(o.input), out(o.output);
  std::optional<io::CloudFormat> written;
  if (single_file_conversion(o)) {
    require(!format_given, "--format",
            "sets the format of the frame files in an output folder; " + o.output +
                " is one file, whose extension sets its format");
    written = io::cloud_format_of(out);
  } else {
    const bool to_folder = fs::is_directory(out) || !out.has_extension();
    if (!to_folder && fs::is_regular_file(in) && io::cloud_format_of(in))
      throw Error(o.output + ": unknown output extension '" + out.extension().string() +
                  "': a cloud is written as .pcd, .ply or .bin (or give a folder)");
    const bool input_found = fs::exists(in) || o.input.find_first_of("*?[") != std::string::npos;
    if (!to_folder && input_found && io::cloud_format_of(out))
      throw Error(o.output + ": names one cloud file, but " + o.input +
                  " is a sequence of frames: give an output folder (e.g. " +
                  (out.parent_path() / out.stem()).string() + "), written as one file per frame");
    written = o.format == "bin" ? io::CloudFormat::kKittiBin : io::CloudFormat::kPcd;
  }
  require(!(o.ascii && o.compressed), "--compressed", "and --ascii exclude each other");
  require(
      !o.compressed || written == io::CloudFormat::kPcd, "--compressed",
      "only PCD has a binary_compressed encoding; the output format is " + io::to_string(*written));
  require(!o.ascii || written != io::CloudFormat::kKittiBin, "--ascii",
          "KITTI .bin has no ASCII encoding; write .pcd or .ply for ASCII");
}

void convert_stream(const ConvertOptions& o) {
  namespace fs = std::filesystem;
  io::SourceOptions so;
  so.topic = o.topic;
  so.metadata = o.metadata;
  auto source = io::FrameSource::open(o.input, so);
  const fs::path dir(o.output);
  if (fs::exists(dir) && !fs::is_directory(dir))
    throw Error(o.output + ": exists and is not a folder (frames are written as " + dir.string() +
                "/000000." + o.format + ", ...)");
  // A folder or glob of frame files read into that same folder would be replaced as it is read.
  std::error_code ec;
  const bool glob = o.input.find_first_of("*?[") != std::string::npos;
  fs::path input_folder;
  if (fs::is_directory(o.input, ec))
    input_folder = o.input;
  else if (glob)
    input_folder = fs::path(o.input).has_parent_path() ? fs::path(o.input).parent_path() : ".";
  if (!input_folder.empty() && fs::equivalent(input_folder, dir, ec))
    throw Error(o.output + ": is the input folder; write the frames to another folder");
  const bool dir_existed = fs::exists(dir);
  fs::create_directories(dir);
  const fs::path times_path = dir / "times.txt";
  io::check_writable(times_path, o.force, {o.input});
  io::WriteOptions w;
  w.overwrite = o.force;
  w.binary = !o.ascii;
  w.compressed = o.compressed;
  std::string times;
  std::size_t unstamped = 0;
  ProgressBar bar(!o.quiet);
  std::size_t written = 0, skipped = 0, points = 0;
  while (auto f = source->next()) {
    if (!f->complete && !o.partial) {
      ++skipped;
      continue;
    }
    const fs::path out = dir / fmt::format("{:06d}.{}", written, o.format);
    io::check_writable(out, o.force, {o.input});
    io::write_cloud(out, f->cloud, w);
    if (written == 0) report_origin(f->cloud, out.string());
    times += fmt::format("{:.9f}\n", f->stamp_s);
    if (f->stamp_s == 0) ++unstamped;
    ++written;
    points += f->cloud.size();
    bar.update(source->progress(), written);
  }
  bar.done();
  warn_source_losses(*source);
  if (written == 0) {
    if (!dir_existed) fs::remove(dir, ec);  // only when still empty
    throw Error(o.input + ": no frame to convert" +
                (skipped ? fmt::format(" (only {} partial sweep{}: --partial writes them)", skipped,
                                       skipped == 1 ? "" : "s")
                         : std::string(" (it holds no scan)")));
  }
  io::write_file_atomic(times_path, times, o.force);
  fmt::print("wrote {} frames ({} points) as {} to {}/ with their stamps in times.txt\n", written,
             points, o.format, o.output);
  if (unstamped)
    warn(
        fmt::format("{} of {} frames carry no time stamp (the input has none): their lines in "
                    "times.txt are 0",
                    unstamped, written));
  if (points == 0) warn(fmt::format("every frame of {} is empty", o.input));
  if (skipped)
    fmt::print("skipped {} partial sweeps at the capture's ends (--partial keeps them)\n", skipped);
  if (o.format == "bin")
    fmt::print(
        "note: KITTI .bin keeps x y z intensity only; use --format pcd to keep ring and time\n");
}
}  // namespace

void add_convert_command(CLI::App& app) {
  auto opts = std::make_shared<ConvertOptions>();
  auto* cmd = app.add_subcommand(
      "convert",
      "Convert a LiDAR file to another format (by extension), or a capture, bag, folder or glob "
      "into a folder of one file per frame");
  cmd->add_option("IN", opts->input,
                  "Input: .bin/.pcd/.ply/.las file, folder or glob of them, .pcap, .bag")
      ->required();
  cmd->add_option("OUT", opts->output,
                  "Output file (.bin, .pcd, .ply) for a single file, else an output folder")
      ->required();
  auto* format = cmd->add_option("--format", opts->format,
                                 "Frame file format in the output folder: pcd or bin")
                     ->capture_default_str()
                     ->check(CLI::IsMember({"pcd", "bin"}));
  cmd->add_option("--topic", opts->topic, "Bag topic of the scans (default: the only one)");
  cmd->add_option("--metadata", opts->metadata,
                  "Ouster metadata JSON (default: <capture>.json beside the capture)");
  cmd->add_flag("-f,--force", opts->force, "Replace existing output files");
  cmd->add_flag("--ascii", opts->ascii, "Write ASCII PCD/PLY instead of binary");
  cmd->add_flag("--compressed", opts->compressed, "Write PCD as binary_compressed");
  cmd->add_flag("--partial", opts->partial,
                "Also write the partial sweeps at the start and end of a capture");
  cmd->add_flag("-q,--quiet", opts->quiet, "No progress bar");
  cmd->callback([opts, format] {
    check_convert_options(*opts, format->count() > 0);
    if (!single_file_conversion(*opts)) return convert_stream(*opts);
    io::check_writable(opts->output, opts->force, {opts->input});
    const PointCloud cloud = io::read_cloud(opts->input);
    if (cloud.empty()) throw Error(opts->input + ": has no points: nothing to convert");
    io::WriteOptions w;
    w.overwrite = opts->force;
    w.binary = !opts->ascii;
    w.compressed = opts->compressed;
    io::write_cloud(opts->output, cloud, w);
    fmt::print("wrote {} points to {}\n", cloud.size(), opts->output);
    report_origin(cloud, opts->output);
  });
}

}  // namespace fieldlidar::app
