// Velodyne and Ouster packet captures as FrameSources, streamed one datagram at a time.
#include <deque>
#include <map>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/ouster.hpp"
#include "fieldlidar/io/pcap.hpp"
#include "fieldlidar/io/velodyne.hpp"
#include "frame_sources.hpp"

namespace fieldlidar::io::detail {
namespace {

constexpr std::uint16_t kVelodyneDataPort = 2368;
constexpr std::size_t kOusterImuBytes = 48;

bool looks_like_velodyne(std::span<const std::uint8_t> payload) {
  return payload.size() == kVelodyneDataPacketBytes && payload[0] == 0xFF &&
         (payload[1] == 0xEE || payload[1] == 0xDD);
}

std::string sizes_seen(const std::map<std::size_t, std::size_t>& sizes) {
  std::string s;
  for (const auto& [bytes, n] : sizes)
    s += (s.empty() ? "" : ", ") + std::to_string(n) + " x " + std::to_string(bytes) + " B";
  return s.empty() ? "no UDP datagrams" : s;
}

/// The capture reader's warning (a truncated tail), if any.
std::vector<std::string> reader_warnings(const PcapReader& reader) {
  if (const auto& t = reader.truncated()) return {*t};
  return {};
}

/// "; <why the capture ended early>" for an error about what the capture lacks, else "".
std::string truncation_note(const PcapReader& reader) {
  return reader.truncated() ? "; " + *reader.truncated() : std::string();
}

/// A finished sweep of a capture as a Frame (stamp = the sweep's own stamp).
Frame sweep_frame(PointCloud cloud, bool complete, std::size_t index,
                  const std::filesystem::path& capture) {
  Frame f;
  f.cloud = std::move(cloud);
  f.stamp_s = f.cloud.stamp_s;
  f.complete = complete;
  f.index = index;
  f.topic = capture.string();
  return f;
}

class VelodynePcapSource final : public FrameSource {
 public:
  VelodynePcapSource(const std::filesystem::path& path, std::optional<VelodyneModel> model)
      : reader_(path) {
    if (model) sensor_ = sensor_model_of(*model);
  }

  std::optional<Frame> next() override {
    for (;;) {
      if (auto s = assembler_.pop())
        return sweep_frame(std::move(s->cloud), s->complete, index_++, reader_.path());
      if (done_) return std::nullopt;
      auto d = reader_.next();
      if (!d) {
        done_ = true;
        if (data_packets_ == 0)
          throw Error(reader_.path().string() + ": no Velodyne data packets (" +
                      std::to_string(kVelodyneDataPacketBytes) +
                      "-byte UDP payloads) in the capture; seen: " + sizes_seen(sizes_) +
                      truncation_note(reader_));
        assembler_.finish();
        continue;
      }
      if (sizes_.size() < 16 || sizes_.count(d->payload.size())) ++sizes_[d->payload.size()];
      if (d->payload.size() == kVelodyneDataPacketBytes) {
        ++data_packets_;
        assembler_.add_packet(d->payload, d->stamp_s, reader_.path().string());
        if (!sensor_ && assembler_.model()) sensor_ = sensor_model_of(*assembler_.model());
      } else if (d->payload.size() != kVelodynePositionPacketBytes &&
                 (d->dst_port == kVelodyneDataPort || d->src_port == kVelodyneDataPort)) {
        throw Error(reader_.path().string() + ": capture record " + std::to_string(d->record) +
                    " carries a " + std::to_string(d->payload.size()) +
                    "-byte datagram on the Velodyne data port 2368; data packets have " +
                    std::to_string(kVelodyneDataPacketBytes) + " bytes");
      }
    }
  }
  std::string format() const override { return "velodyne-pcap"; }
  std::optional<SensorModel> sensor() const override { return sensor_; }
  double progress() const override { return reader_.progress(); }
  std::vector<std::string> warnings() const override { return reader_warnings(reader_); }

 private:
  PcapReader reader_;
  VelodyneSweepAssembler assembler_;
  std::optional<SensorModel> sensor_;
  std::size_t index_ = 0, data_packets_ = 0;
  std::map<std::size_t, std::size_t> sizes_;
  bool done_ = false;
};

class OusterPcapSource final : public FrameSource {
 public:
  OusterPcapSource(const std::filesystem::path& path, OusterMetadata meta, std::string meta_source)
      : reader_(path),
        assembler_(std::move(meta)),
        sensor_(sensor_model_of(assembler_.decoder().metadata())),
        meta_source_(std::move(meta_source)) {}

  std::optional<Frame> next() override {
    for (;;) {
      if (auto of = assembler_.pop())
        return sweep_frame(std::move(of->cloud), of->complete, index_++, reader_.path());
      if (done_) return std::nullopt;
      auto d = reader_.next();
      if (!d) {
        done_ = true;
        if (lidar_packets_ == 0)
          throw Error(reader_.path().string() + ": no Ouster lidar packet of the " +
                      std::to_string(assembler_.decoder().packet_bytes()) + " bytes that " +
                      meta_source_ + " implies; datagrams seen: " + sizes_seen(sizes_) +
                      " (is this the metadata of this capture?)" + truncation_note(reader_));
        assembler_.finish();
        continue;
      }
      const auto& meta = assembler_.decoder().metadata();
      if (sizes_.size() < 16 || sizes_.count(d->payload.size())) ++sizes_[d->payload.size()];
      if (d->payload.size() == kOusterImuBytes) {
        imu_.push_back(decode_ouster_imu_packet(d->payload));
      } else if (d->payload.size() == assembler_.decoder().packet_bytes()) {
        ++lidar_packets_;
        assembler_.add_packet(d->payload, reader_.path().string());
      } else if (d->dst_port == meta.udp_port_lidar || d->dst_port == 7502) {
        throw Error(reader_.path().string() + ": capture record " + std::to_string(d->record) +
                    " carries a " + std::to_string(d->payload.size()) +
                    "-byte lidar datagram but " + meta_source_ + " (" + to_string(meta.profile) +
                    ", " + std::to_string(meta.pixels_per_column) + " beams) implies " +
                    std::to_string(assembler_.decoder().packet_bytes()) +
                    ": the metadata does not belong to this capture");
      }
    }
  }
  std::string format() const override { return "ouster-pcap"; }
  std::optional<SensorModel> sensor() const override { return sensor_; }
  double progress() const override { return reader_.progress(); }
  std::vector<std::string> warnings() const override { return reader_warnings(reader_); }
  std::vector<ImuSample> imu_until(double until_s) override {
    std::vector<ImuSample> out;
    while (!imu_.empty() && imu_.front().stamp_s <= until_s) {
      const auto& s = imu_.front();
      out.push_back({s.stamp_s, s.gyro_rad_s, s.accel_m_s2});
      imu_.pop_front();
    }
    return out;
  }

 private:
  PcapReader reader_;
  OusterFrameAssembler assembler_;
  SensorModel sensor_;
  std::string meta_source_;
  std::deque<OusterImuSample> imu_;
  std::size_t index_ = 0, lidar_packets_ = 0;
  std::map<std::size_t, std::size_t> sizes_;
  bool done_ = false;
};

}  // namespace

std::unique_ptr<FrameSource> open_pcap(const std::filesystem::path& capture,
                                       const SourceOptions& options) {
  auto open_ouster = [&](const std::filesystem::path& meta_path) -> std::unique_ptr<FrameSource> {
    return std::make_unique<OusterPcapSource>(capture, read_ouster_metadata(meta_path),
                                              "metadata " + meta_path.string());
  };
  if (!options.metadata.empty()) return open_ouster(options.metadata);
  // Look at the first datagrams: Velodyne data packets are recognisable by size and block flag.
  std::map<std::size_t, std::size_t> sizes;
  std::string cut;  // why the capture ended within the datagrams looked at, if it did
  {
    PcapReader peek(capture);
    for (int i = 0; i < 256; ++i) {
      const auto d = peek.next();
      if (!d) break;
      if (looks_like_velodyne(d->payload)) {
        std::optional<VelodyneModel> model;
        try {
          std::vector<VelodyneReturn> scratch;
          model = decode_velodyne_packet(d->payload, scratch).model;
        } catch (const Error&) {
          // reported with its packet number when the stream reaches it
        }
        return std::make_unique<VelodynePcapSource>(capture, model);
      }
      ++sizes[d->payload.size()];
    }
    cut = truncation_note(peek);
  }
  auto sidecar = capture;
  sidecar.replace_extension(".json");
  if (std::filesystem::exists(sidecar)) return open_ouster(sidecar);
  throw Error(capture.string() + ": no Velodyne data packets among the first datagrams (" +
              sizes_seen(sizes) + ") and no Ouster metadata: pass --metadata FILE.json or put " +
              sidecar.filename().string() + " beside the capture" + cut);
}

}  // namespace fieldlidar::io::detail
