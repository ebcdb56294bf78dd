// FrameSource::open: the input kind from the path; single files and file lists.
#include "fieldlidar/io/frame_source.hpp"

#include <fnmatch.h>

#include <algorithm>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/cloud_file.hpp"
#include "fieldlidar/io/rosbag_reader.hpp"
#include "fieldlidar/io/trajectory_io.hpp"
#include "frame_sources.hpp"

namespace fieldlidar::io {

FrameSource::~FrameSource() = default;
std::optional<SensorModel> FrameSource::sensor() const {
  return std::nullopt;
}
std::vector<ImuSample> FrameSource::imu_until(double) {
  return {};
}
std::vector<OdometrySample> FrameSource::odometry_until(double) {
  return {};
}
std::vector<std::string> FrameSource::warnings() const {
  return {};
}

namespace detail {
namespace {

/// Reads one file per frame, in the given order; only the current file is in memory. Frames are
/// stamped by `times` (one per file) when given, else by what their file says (often 0).
class CloudFileSource final : public FrameSource {
 public:
  CloudFileSource(std::vector<std::filesystem::path> files, std::string format,
                  std::vector<double> times, std::vector<std::string> warnings)
      : files_(std::move(files)),
        format_(std::move(format)),
        times_(std::move(times)),
        warnings_(std::move(warnings)) {}
  std::optional<Frame> next() override {
    if (next_ >= files_.size()) return std::nullopt;
    const auto& path = files_[next_];
    Frame f;
    f.cloud = read_cloud(path);
    if (next_ < times_.size()) f.cloud.stamp_s = times_[next_];
    f.stamp_s = f.cloud.stamp_s;
    f.index = next_++;
    f.topic = path.string();
    return f;
  }
  std::string format() const override { return format_; }
  double progress() const override {
    return files_.empty() ? 1.0 : double(next_) / double(files_.size());
  }
  std::vector<std::string> warnings() const override { return warnings_; }

 private:
  std::vector<std::filesystem::path> files_;
  std::string format_;
  std::vector<double> times_;
  std::vector<std::string> warnings_;
  std::size_t next_ = 0;
};

/// A sequence folder's clock: the times.txt in `dir` or beside it (KITTI's velodyne/ and a
/// simulator's pcd/ lie beside theirs), one stamp (s) per frame file. One that lists another
/// number of frames is not used, and says so in `warnings`.
std::vector<double> sequence_times(const std::filesystem::path& dir, std::size_t frames,
                                   std::vector<std::string>& warnings) {
  namespace fs = std::filesystem;
  for (const fs::path& p : {dir / "times.txt", dir.parent_path() / "times.txt"}) {
    if (!fs::is_regular_file(p)) continue;
    std::vector<double> times;
    try {
      times = read_kitti_times(p);
    } catch (const Error& e) {
      warnings.push_back(std::string(e.what()) + ": not used as the frames' clock");
      return {};
    }
    if (times.size() == frames) return times;
    warnings.push_back(p.string() + " lists " + std::to_string(times.size()) + " stamps for " +
                       std::to_string(frames) +
                       " frame files: not used (the frames carry their files' own stamps)");
    return {};
  }
  return {};
}

/// The cloud files directly in `dir`, in name order.
std::vector<std::filesystem::path> cloud_files_in(const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.is_regular_file() && cloud_format_of(e.path())) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace

std::unique_ptr<FrameSource> open_cloud_files(std::vector<std::filesystem::path> files,
                                              const std::string& description,
                                              std::vector<double> times,
                                              std::vector<std::string> warnings) {
  if (files.empty()) throw Error(description + ": no .bin, .pcd, .ply or .las files");
  const auto first = cloud_format_of(files.front());
  for (const auto& f : files)
    if (cloud_format_of(f) != first)
      throw Error(description + ": mixes cloud formats (" + files.front().filename().string() +
                  " and " + f.filename().string() + ")");
  return std::make_unique<CloudFileSource>(std::move(files), to_string(*first), std::move(times),
                                           std::move(warnings));
}

}  // namespace detail

std::unique_ptr<FrameSource> FrameSource::open(const std::filesystem::path& input,
                                               const SourceOptions& options) {
  namespace fs = std::filesystem;
  const std::string name = input.filename().string();
  const bool glob = name.find_first_of("*?[") != std::string::npos;
  if (glob) {
    const fs::path dir = input.has_parent_path() ? input.parent_path() : fs::path(".");
    if (!fs::is_directory(dir))
      throw Error(input.string() + ": folder " + dir.string() + " does not exist");
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(dir))
      if (e.is_regular_file() && cloud_format_of(e.path()) &&
          ::fnmatch(name.c_str(), e.path().filename().c_str(), 0) == 0)
        files.push_back(e.path());
    std::sort(files.begin(), files.end());
    return detail::open_cloud_files(std::move(files), input.string());
  }
  if (!fs::exists(input)) throw Error(input.string() + ": no such file or folder");
  if (fs::is_directory(input)) {
    fs::path dir = input;
    auto files = detail::cloud_files_in(dir);
    for (const char* sub : {"pcd", "velodyne"}) {  // a simulator's output, a KITTI sequence
      if (!files.empty() || !fs::is_directory(input / sub)) continue;
      dir = input / sub;
      files = detail::cloud_files_in(dir);
    }
    std::vector<std::string> warnings;
    auto times =
        files.empty() ? std::vector<double>{} : detail::sequence_times(dir, files.size(), warnings);
    return detail::open_cloud_files(std::move(files), input.string(), std::move(times),
                                    std::move(warnings));
  }
  const std::string ext = extension_of(input);
  if (ext == "pcap" || ext == "pcapng" || ext == "cap") return detail::open_pcap(input, options);
  if (ext == "bag") return open_rosbag(input, options.topic);
  if (cloud_format_of(input)) return detail::open_cloud_files({input}, input.string());
  throw Error(input.string() + ": unsupported input '" + input.extension().string() +
              "' (expected .bin, .pcd, .ply, .las, a folder or glob of them, .pcap or .bag)");
}

}  // namespace fieldlidar::io
