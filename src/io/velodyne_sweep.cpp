// VelodyneSweepAssembler: the stream of decoded firings cut into sweeps at the azimuth wrap.
#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/velodyne.hpp"
#include "velodyne_tables.hpp"

namespace fieldlidar::io {

void VelodyneSweepAssembler::add_packet(std::span<const std::uint8_t> bytes, double capture_stamp_s,
                                        const std::string& source) {
  constexpr int kFullTurnCdeg = detail::kVelodyneFullTurnCdeg;
  const std::size_t packet = packets_++;
  scratch_.clear();
  VelodynePacketInfo info;
  try {
    info = decode_velodyne_packet(bytes, scratch_);
  } catch (const Error& e) {
    throw Error(source + ": data packet " + std::to_string(packet) + ": " + e.what());
  }
  if (model_ && *model_ != info.model)
    throw Error(source + ": data packet " + std::to_string(packet) + " is from a " +
                to_string(info.model) + " but the capture began with a " + to_string(*model_) +
                " (mixed sensors in one capture: split it by port or source address)");
  if (mode_ && *mode_ != info.mode)
    throw Error(source + ": data packet " + std::to_string(packet) + " switches return mode from " +
                to_string(*mode_) + " to " + to_string(info.mode));
  model_ = info.model;
  mode_ = info.mode;

  const std::int64_t ts = info.timestamp_us;
  if (last_timestamp_us_ >= 0 && ts + 1800'000'000LL < last_timestamp_us_) hour_offset_s_ += 3600;
  last_timestamp_us_ = ts;
  const double packet_sensor_s = hour_offset_s_ + double(ts) * 1e-6;

  for (const VelodyneReturn& r : scratch_) {
    const int az = r.firing_azimuth_cdeg;
    if (last_azimuth_cdeg_ >= 0) {
      if (az + kFullTurnCdeg / 2 < last_azimuth_cdeg_) {
        close_sweep(started_at_wrap_);
        started_at_wrap_ = true;
      } else if (az > last_azimuth_cdeg_ && az - last_azimuth_cdeg_ <= 500) {
        az_span_cdeg_ += az - last_azimuth_cdeg_;  // steps above 5 deg are gaps (lost packets)
      }
    }
    last_azimuth_cdeg_ = az;
    if (!started_) {
      started_ = true;
      start_sensor_s_ = packet_sensor_s + r.point.time;
      start_capture_s_ = capture_stamp_s + r.point.time;
    }
    if (!r.valid) continue;
    Point p = r.point;
    p.time = float(packet_sensor_s + double(r.point.time) - start_sensor_s_);
    points_.push_back(p);
  }
}

void VelodyneSweepAssembler::close_sweep(bool complete) {
  if (!started_) return;
  VelodyneSweep s;
  s.complete = complete;
  s.azimuth_span_deg = az_span_cdeg_ / 100.0;
  s.cloud.points = std::move(points_);
  s.cloud.stamp_s = start_capture_s_;
  s.cloud.fields.intensity = s.cloud.fields.ring = s.cloud.fields.time = true;
  s.cloud.width = std::uint32_t(s.cloud.points.size());
  s.cloud.height = 1;
  ready_.push_back(std::move(s));
  points_ = {};
  points_.reserve(ready_.back().cloud.size() + 1024);
  started_ = false;
  az_span_cdeg_ = 0;
}

void VelodyneSweepAssembler::finish() {
  close_sweep(false);
}

std::optional<VelodyneSweep> VelodyneSweepAssembler::pop() {
  if (ready_.empty()) return std::nullopt;
  VelodyneSweep s = std::move(ready_.front());
  ready_.pop_front();
  return s;
}

}  // namespace fieldlidar::io
